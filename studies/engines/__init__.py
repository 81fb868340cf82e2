"""The engines study (README.md)."""
