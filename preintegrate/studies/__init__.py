"""Measured studies of the report: each module runs one study and returns, plots and tabulates its numbers."""
