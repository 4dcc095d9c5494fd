"""seismo3d.registration."""
