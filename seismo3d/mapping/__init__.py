"""seismo3d.mapping."""
