"""The same geometry rebuilt in python-fcl (an independent collision library), placed with
Pinocchio's forward kinematics, for checking World's answers."""
import fcl
import numpy as np
import pinocchio as pin


def fcl_geometry(go, mesh_vertices=None):
    import coal
    import trimesh
    g = go.geometry
    if isinstance(g, coal.Capsule):
        return fcl.Capsule(g.radius, 2 * g.halfLength)
    if isinstance(g, coal.Sphere):
        return fcl.Sphere(g.radius)
    if isinstance(g, coal.Box):
        return fcl.Box(*(2 * np.asarray(g.halfSide)))
    if isinstance(g, coal.Cylinder):
        return fcl.Cylinder(g.radius, 2 * g.halfLength)
    if mesh_vertices is not None:
        V, F = mesh_vertices
    else:
        tm = trimesh.load(go.meshPath, force="mesh")
        V, F = np.asarray(tm.vertices) * np.asarray(go.meshScale), np.asarray(tm.faces)
    m = fcl.BVHModel()
    m.beginModel(len(V), len(F))
    m.addSubModel(V, F)
    m.endModel()
    return m


class FclWorld:
    def __init__(self, world, meshes=None):
        self.w = world
        self.geoms = []
        for k, go in enumerate(world.geometry_model.geometryObjects):
            mv = (meshes or {}).get(go.name)
            self.geoms.append((go, fcl_geometry(go, mv)))

    def pair_distances(self, q):
        r = self.w.robot
        data = r.model.createData()
        pin.forwardKinematics(r.model, data, r.q_pin(q))
        objs = []
        for go, g in self.geoms:
            M = data.oMi[go.parentJoint] * go.placement
            objs.append(fcl.CollisionObject(g, fcl.Transform(M.rotation, M.translation)))
        out = []
        for i, j in self.w._pairs:
            creq, cres = fcl.CollisionRequest(), fcl.CollisionResult()
            hit = fcl.collide(objs[i], objs[j], creq, cres) > 0
            dres = fcl.DistanceResult()
            d = fcl.distance(objs[i], objs[j], fcl.DistanceRequest(), dres)
            out.append((hit, d))
        return out
