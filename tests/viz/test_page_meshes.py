"""Meshes on the teach page are bounded: decimated to the page's face budget (with a note), refused
above the per-mesh cap."""
import numpy as np
import pytest


def test_teach_mesh_faces_are_bounded(tmp_path, monkeypatch):
    """A mesh with more triangles than a page may hold is decimated until it fits, with a note
    giving both counts — and the decimated vertices stay on the unit sphere (within the
    clustering bound). The page cap is lowered to 5,000 here to keep the test small."""
    import trimesh

    import robokit.viz._meshes as vm
    from robokit.errors import RobokitWarning

    monkeypatch.setattr(vm, "MAX_PAGE_FACES", 5_000)
    sphere = trimesh.creation.icosphere(subdivisions=6, radius=1.0)  # 81,920 faces
    p = tmp_path / "s.stl"
    sphere.export(p)
    with pytest.warns(RobokitWarning, match=r"81920 triangles decimated to \d+ for the page"):
        parts = vm.mesh_parts(p, 0.01)
    faces = sum(len(F) for _, F, _ in parts)
    assert 0 < faces <= 5_000
    V = np.vstack([V for V, _, _ in parts])
    assert np.all(np.abs(np.linalg.norm(V, axis=1) - 1.0) < 0.1)


def test_teach_mesh_face_cap_refuses_by_count(tmp_path, monkeypatch):
    """The face cap refuses with the count (the cap lowered to 10,000 here, so that the test does
    not have to write a 2M-triangle file)."""
    import trimesh

    import robokit.viz._meshes as vm
    from robokit.errors import InputError

    monkeypatch.setattr(vm, "MAX_MESH_FACES", 10_000)
    p = tmp_path / "s.obj"
    trimesh.creation.icosphere(subdivisions=5).export(p)  # 20,480 faces
    with pytest.raises(InputError, match="s.obj: mesh of more than 10000 triangles"):
        vm.mesh_parts(p, 0.001)
