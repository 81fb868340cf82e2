"""The adaptation study (README.md)."""
