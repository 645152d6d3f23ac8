"""The experiment files (one YAML per experiment, schema in README.md), shipped as the package
``reproductions.configs`` (pyproject.toml maps it onto this folder) and found by ``api.config_dir()``."""
