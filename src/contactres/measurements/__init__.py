"""Measured data: the schema of every table, the readers, validated tables, synthetic data."""
