"""Docs generated from the code: what a reader should never have to keep in step by hand."""
