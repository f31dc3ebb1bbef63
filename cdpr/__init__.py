"""cdpr."""
