"""The navigation study (README.md)."""
