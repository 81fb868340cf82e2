"""MAP-Elites map generation and M-BOA adaptation (built out in the adaptation issues)."""
