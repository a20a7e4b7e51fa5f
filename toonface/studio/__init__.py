"""The studio: a local web page for playing with a face (test mode) served by ``toonface studio``."""
