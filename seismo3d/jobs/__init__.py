"""The commands' end-to-end jobs: read inputs, call the applications, write outputs (cli.py wraps them)."""
