"""The session as one phone sees it (the state), built from the other domains."""
