"""What the command line runs: the demo and the reproductions of the papers' figures."""
