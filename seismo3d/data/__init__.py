"""seismo3d.data."""
