"""seismo3d.viz."""
