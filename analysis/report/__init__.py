"""The report (Markdown and HTML): fitted against published numbers, each with its verdict."""
