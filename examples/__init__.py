"""The example files of ``resal fit`` (one synthetic CSV per kind, labelled so in its first lines), shipped as the
package ``reproductions.examples`` (pyproject.toml maps it onto this folder), found by ``locate.examples_dir()``
and copied out by ``resal examples``. ``generate.py`` writes them, in a checkout: ``python examples/generate.py``."""
