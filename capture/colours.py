"""The dot colours the tracker knows, apart from it so that listing them imports no OpenCV."""

#: OpenCV hue ranges (0-180) of the dot colours we know.
HUES = {"blue": (95, 130), "green": (40, 85), "red": (170, 8), "yellow": (20, 35)}
