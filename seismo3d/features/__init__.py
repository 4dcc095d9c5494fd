"""seismo3d.features."""
