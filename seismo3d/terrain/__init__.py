"""seismo3d.terrain."""
