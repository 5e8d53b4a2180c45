"""Write robocasa's procedural cabinet fixtures as stand-alone MJCF files.

Run by ``rest2art bench prepare`` with the Python of a separate environment that holds
robocasa and its pinned robosuite and MuJoCo (they conflict with this project's), never
imported by rest2art itself::

    python robocasa_export.py OUT_DIR < items.json

``items.json`` is a list of {"name", "kind", "size", "panel", "handle", "orientation", "stack"}:
kind is ``hinge`` (two doors), ``single`` (one door, hinged on ``orientation``'s side) or
``drawer``; ``stack`` (drawer only) puts that many drawers one above the other in one model,
as robocasa's kitchens stack them. Each model is written to OUT_DIR/<name>.xml with its
textures removed (their files stay in the other environment), its colours kept, and its angles
in radians as robocasa's kitchens compile them.
"""

from __future__ import annotations

import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path


def _fixture(item: dict, name: str, size: list[float]):
    from robocasa.models.fixtures.cabinets import Drawer, HingeCabinet, SingleCabinet

    common = dict(name=name, size=size, panel_type=item["panel"], handle_type=item["handle"])
    if item["kind"] == "hinge":
        return HingeCabinet(**common)
    if item["kind"] == "single":
        return SingleCabinet(orientation=item.get("orientation", "right"), **common)
    if item["kind"] == "drawer":
        return Drawer(**common)
    raise ValueError(f"unknown kind {item['kind']!r}")


def _strip_textures(root: ET.Element) -> None:
    """Drop <texture> elements and the materials' references to them."""
    for asset in root.iter("asset"):
        for texture in list(asset.findall("texture")):
            asset.remove(texture)
    for material in root.iter("material"):
        material.attrib.pop("texture", None)


def export(item: dict) -> str:
    """The MJCF text of one item: a fixture, or ``stack`` drawers one above the other."""
    count = int(item.get("stack", 1))
    w, d, h = item["size"]
    root = None
    for k in range(count):
        fixture = _fixture(item, f"{item['name']}_{k}", [w, d, h])
        model = ET.fromstring(fixture.get_xml())
        if root is None:
            root = model
            world = root.find("worldbody")
            continue
        # the k-th drawer's bodies go on top of the ones before, its assets beside theirs
        for body in model.find("worldbody"):
            x, y, z = (float(v) for v in body.get("pos", "0 0 0").split())
            body.set("pos", f"{x} {y} {z + k * h}")
            world.append(body)
        for section in ("asset", "default"):
            src, dst = model.find(section), root.find(section)
            if src is not None and dst is not None:
                dst.extend(list(src))
    _strip_textures(root)
    # robocasa's kitchens compile every fixture in radians; some templates leave that out
    compiler = root.find("compiler")
    if compiler is None:
        compiler = ET.Element("compiler")
        root.insert(0, compiler)
    compiler.set("angle", "radian")
    root.set("model", item["name"])
    return ET.tostring(root, encoding="unicode")


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for item in json.load(sys.stdin):
        tmp = out / f"{item['name']}.xml.tmp"
        tmp.write_text(export(item))
        tmp.replace(out / f"{item['name']}.xml")


if __name__ == "__main__":
    main()
