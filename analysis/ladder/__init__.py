"""The reproduction ladder: a finished study collected into a rung, and the ladder's tables by claim."""
