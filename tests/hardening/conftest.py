"""The hardening suite's fixtures and helpers are shared with the concept folders: see
tests/conftest.py (``write``, ``main_cli``) and tests/support/ (``hardening_support``)."""
