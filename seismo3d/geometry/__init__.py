"""seismo3d.geometry."""
