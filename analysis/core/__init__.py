"""The tidy pull table and what every room shares: units, physics, the paper's numbers, result types, paths."""
