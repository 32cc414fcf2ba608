"""Drawing the answer on a photo (OpenCV), in the colours both phones share."""
