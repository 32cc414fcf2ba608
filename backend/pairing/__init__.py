"""Starting a search, joining it with a code (guessing limited), knowing who asks, ending it."""
