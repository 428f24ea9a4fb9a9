"""Cycles' AO bake as the two Blender comparisons use it (scripts/blender-vs-cycles.py and
scripts/blender-vs-cycles-analytic.py): the same render settings, so both scripts ask Cycles the
same question, and the values of a color attribute that a bake wrote."""

import bpy
import numpy as np


def use_cycles_ao(scene, samples, distance):
    """Cycles on the CPU, `samples` AO rays per vertex (one per render sample), no denoising and
    no adaptive sampling (each would change the answer), AO rays `distance` long (the world's AO
    distance; a world is made when the scene has none)."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.light_settings.distance = distance


def attribute_values(attribute):
    """The first channel of every element of a color attribute (a bake writes AO into r, g and b)."""
    rgba = np.empty(len(attribute.data) * 4, np.float32)
    attribute.data.foreach_get("color", rgba)
    return rgba.reshape(-1, 4)[:, 0]
