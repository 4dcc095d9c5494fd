"""seismo3d.seismic."""
