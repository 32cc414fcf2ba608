"""A participant's photo: stored upright without metadata, shown back, cropped."""
