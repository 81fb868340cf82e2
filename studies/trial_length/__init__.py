"""The trial length study (README.md)."""
