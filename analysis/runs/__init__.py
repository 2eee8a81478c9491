"""The engine's run files (HDF5, `granudrag pull`) into rows of the table, each drag with its own error."""
