"""Scenes: validated device parameters, materials, the built-in seed devices and TOML loading."""

from modalfe.scene.loading import load_scene, scene_from_dict, scene_from_toml
from modalfe.scene.scene import Analysis, Drive, MeshSettings, Scene, Target, WorkingMode

__all__ = ["Analysis", "Drive", "MeshSettings", "Scene", "Target", "WorkingMode", "load_scene", "scene_from_dict",
           "scene_from_toml"]
