"""Animated GIF of a physics run, rendered with PyBullet's TinyRenderer (no display needed)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import pybullet as pb
from matplotlib.colors import to_rgb
from PIL import Image

from rdcd_core.outputs import write_with
from sim.plot import ROLE_COLOURS
from vm.roles import RoleTable

if TYPE_CHECKING:
    from sim.world import PhysicsWorld

WIDTH, HEIGHT = 320, 240
FRAME_EVERY_S = 0.5  # one frame per run chunk
FRAME_MS = 100  # playback: 5× faster than simulated time
MAX_FRAMES = 400
NO_ROLE_RGB = (215 / 255, 215 / 255, 215 / 255)


class GifRecorder:
    def __init__(self, world: PhysicsWorld, roles: RoleTable) -> None:
        self.world = world
        self.roles = roles
        self.frames: list[Image.Image] = []
        self._shown: dict[int, int] = {}
        names = sorted(roles.names.values())
        self._colour = {name: to_rgb(ROLE_COLOURS[i % len(ROLE_COLOURS)]) for i, name in enumerate(names)}

    def _paint_roles(self) -> None:
        w = self.world
        if getattr(self, "_robot", None) is not w.robot:  # new bodies after a change of shape
            self._robot, self._shown = w.robot, {}
        for mid, runtime in w.runtimes.items():
            if self._shown.get(mid) == runtime.role or mid not in w.robot.shell_visual:
                continue
            self._shown[mid] = runtime.role
            name = self.roles.name(runtime.role) if runtime.role else None
            rgb = self._colour.get(name or "", NO_ROLE_RGB)
            link, shape = w.robot.shell_visual[mid]
            pb.changeVisualShape(w.robot.modules[mid].body, link, shapeIndex=shape, rgbaColor=[*rgb, 1.0],
                                 physicsClientId=w.client)

    def capture(self) -> None:
        if len(self.frames) >= MAX_FRAMES:
            return
        self._paint_roles()
        w = self.world
        x, y = w.centre()
        view = pb.computeViewMatrixFromYawPitchRoll((x, y, 0.1), 1.4, -20.0, -35.0, 0.0, 2,
                                                    physicsClientId=w.client)
        proj = pb.computeProjectionMatrixFOV(50.0, WIDTH / HEIGHT, 0.05, 20.0, physicsClientId=w.client)
        _, _, rgba, _, _ = pb.getCameraImage(WIDTH, HEIGHT, view, proj, renderer=pb.ER_TINY_RENDERER,
                                             physicsClientId=w.client)
        image = Image.frombytes("RGBA", (WIDTH, HEIGHT), bytes(bytearray(_flat(rgba)))).convert("RGB")
        self.frames.append(image.quantize(colors=64))

    def save(self, path: str) -> None:
        """Writes the GIF atomically (a temporary file beside ``path``, then renamed)."""
        if not self.frames:
            self.capture()
        write_with(path, lambda file: self.frames[0].save(
            file, format="GIF", save_all=True, append_images=self.frames[1:], duration=FRAME_MS, loop=0,
            optimize=True))


def _flat(rgba: object) -> list[int]:
    """getCameraImage gives a flat list or a numpy array, depending on the build."""
    try:
        return rgba.reshape(-1).tolist()  # type: ignore[union-attr]
    except AttributeError:
        return list(rgba)  # type: ignore[call-overload]
