"""robokit.collision — collision model of a robot and its surroundings.

Modules: ``shapes`` (the obstacles ``Box``, ``Sphere``, ``Cylinder``, ``Mesh``), ``world``
(:class:`World`: robot geometry + obstacles in one ``pinocchio.GeometryModel``, queried
with coal through Pinocchio; self-collision pairs computed once per robot), ``scene``
(scene YAML files of obstacles).
"""
from robokit.collision.shapes import Box, Cylinder, Mesh, Obstacle, Sphere
from robokit.collision.scene import load_scene, pose_from_xyz_rpy
from robokit.collision.world import SelfCollisionPairs, World, WorldState, self_collision_pairs

__all__ = ["World", "WorldState", "SelfCollisionPairs", "Box", "Sphere", "Cylinder", "Mesh", "Obstacle", "self_collision_pairs", "load_scene", "pose_from_xyz_rpy"]
