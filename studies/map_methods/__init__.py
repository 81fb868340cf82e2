"""The map methods study (README.md)."""
