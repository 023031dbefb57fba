"""robokit.dynamics — see the module docstrings inside."""

__all__: list[str] = []
