"""What each ``seismo3d`` command does end to end: read the inputs, call the applications, write the outputs."""
