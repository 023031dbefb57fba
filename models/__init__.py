"""The robot models robokit ships: ``<name>.yaml`` (a DH table) and its generated ``<name>.urdf``.

This folder is installed as the package ``robokit.models``; robokit finds the files with
``importlib.resources``, the same way from a wheel, an sdist or an editable install.
"""
