# SPDX-License-Identifier: MIT
"""view.py, the ParaView script every run with XDMF output writes into its folder.

The script itself is ``view_template.py`` (plain Python, readable and importable on its own);
the run fills in its own values between the template's ``# <run>`` and ``# </run>`` lines: the
series it writes, the tube's radius, the spheres' size and which way is up. Usage and what it
shows: docs/user-guide.md, "Viewing a run in ParaView"."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

TEMPLATE = Path(__file__).with_name("view_template.py")
_RUN_BLOCK = re.compile(r"# <run>.*?\n(.*?)# </run>\n", re.S)


@dataclass(frozen=True)
class ViewConfig:
    """What view.py needs to know of the run."""

    scene: str
    series: tuple[str, ...]  # the series written: "beams", and "sliders", "masses" if the scene has them
    section_half: float  # the largest half extent of a beam's section (m)
    extent: float  # the diagonal of the structure's bounding box in the reference configuration (m)
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)  # against gravity
    folder: str = "."  # where the run writes view.py: the script's last resort to find the series

    @property
    def tube_radius(self) -> float:
        """The tubes' radius: the section's, but at least 0.4 % of the structure's size. A rope of
        12 mm across a 20 m span is a fraction of a pixel in a picture of the whole; 0.4 % of the
        extent is about 5 pixels in a 1280 pixel wide picture: thin, but seen."""
        return max(self.section_half, 0.004 * self.extent, 1e-9)


def up_direction(gravity: list[float] | None) -> tuple[float, float, float]:
    """The picture's up: against gravity, else +z."""
    norm = math.sqrt(sum(g * g for g in gravity)) if gravity else 0.0
    if norm == 0.0:
        return (0.0, 0.0, 1.0)
    return tuple(0.0 - g / norm for g in gravity)  # type: ignore[return-value]  (0.0 - 0.0: no -0.0)


def view_script(config: ViewConfig) -> str:
    """The text of view.py for a run."""
    r = config.tube_radius
    values = (f"SCENE = {config.scene!r}\n"
              f"SERIES = {tuple(config.series)!r}  # the series the run writes, of beams, sliders, guides, masses, bodies\n"
              f"TUBE_RADIUS = {r!r}  # m: max(section half size, 0.004 x the structure's extent)\n"
              f"SPHERE_DIAMETER = {{'sliders': {4 * r!r}, 'guides': {5 * r!r}, 'masses': {6 * r!r}, "
              f"'bodies': {10 * r!r}}}  # m: 4, 5, 6 and 10 tube radii\n"
              f"UP = {tuple(float(u) for u in config.up)!r}  # against gravity: the picture's up\n"
              f"WRITTEN_IN = {config.folder!r}  # the folder the run wrote this script into (if neither __file__ "
              f"nor --script tells)\n")
    text = TEMPLATE.read_text()
    block = _RUN_BLOCK.search(text)
    if block is None:
        raise RuntimeError(f"{TEMPLATE} has no '# <run>' ... '# </run>' block to fill in")
    return text[:block.start(1)] + values + text[block.end(1):]
