"""robokit.viz — meshcat scenes and HTML export (imported on demand: `import robokit.viz`)."""

__all__: list[str] = []
