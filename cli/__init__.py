"""The ``resal`` command line."""
