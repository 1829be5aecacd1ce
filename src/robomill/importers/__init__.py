"""Importers: native instrument exports converted into the raw-data contract."""
