"""The transfer study (README.md)."""
