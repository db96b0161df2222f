"""The wheel/rail patch tests: their synthetic gaps are in ``patch_gaps.py`` beside this file (importable because
pytest puts a conftest's directory on the path)."""
