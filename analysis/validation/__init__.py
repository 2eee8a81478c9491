"""The validation studies compared with their reference protocol, and pooled over studies."""
