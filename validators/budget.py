"""Checks on the collision geometry as a whole, before any simulator runs.

* budget: hulls per part, hulls per asset and corners per hull in the exported files, against
  the export's budget (hull count is simulation speed: every hull is a geom each step);
* decomposition: a hollow part (a carcass, a drawer box) whose collision is one convex hull
  holds its drawers inside a solid block; the collision stage records why (CoACD timed out or
  failed) and this turns it into a finding with that reason.
"""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree as ET

from rest2art.config import ExportConfig
from rest2art.validators import Finding


def obj_vertex_count(path: Path) -> int:
    """Vertices ('v' lines) of an OBJ file."""
    with open(path, "rb") as f:
        return sum(1 for line in f if line.startswith(b"v "))


def check_hull_budget(asset_dir: str | Path, name: str, config: ExportConfig = ExportConfig()) -> Finding:
    """Hull counts and corners of NAME.urdf's collision meshes against the budget in ``config``."""
    asset_dir = Path(asset_dir)
    counts, corners = {}, {}
    for link in ET.parse(asset_dir / f"{name}.urdf").getroot().iter("link"):
        files = [m.get("filename", "") for m in link.iterfind("collision/geometry/mesh")]
        counts[link.get("name")] = len(files)
        corners[link.get("name")] = max((obj_vertex_count(asset_dir / f) for f in files if (asset_dir / f).is_file()),
                                        default=0)
    total = sum(counts.values())
    problems = [f"{link}: {n} hulls (budget {config.max_hulls_per_part})" for link, n in counts.items()
                if n > config.max_hulls_per_part]
    if total > config.max_hulls_per_asset:
        problems.append(f"{total} hulls in the asset (budget {config.max_hulls_per_asset})")
    problems += [f"{link}: a hull of {n} corners (budget {config.max_hull_vertices})" for link, n in corners.items()
                 if n > config.max_hull_vertices]
    data = {"hulls": counts, "total": total, "max_corners": corners,
            "budget": {"per_part": config.max_hulls_per_part, "per_asset": config.max_hulls_per_asset,
                       "corners": config.max_hull_vertices}}
    most = max(counts.values(), default=0)
    message = f"{total} hulls, at most {most} per part" if not problems else "; ".join(problems)
    return Finding("collision", "budget", not problems, message, data)


def check_decomposition(metadata: dict) -> Finding:
    """The collision stage's record (articulation metadata ``collision``: per part its methods,
    whether it is hollow, what failed) as a finding: a hollow part left as one hull fails,
    with the reason; a failure that boxes stood in for is reported and passes."""
    record = metadata.get("collision") or {}
    failed, covered = {}, {}
    for part, entry in record.items():
        failures = entry.get("failures") or []
        if not failures:
            continue
        if entry.get("hollow") and entry.get("hulls", 0) <= 1:
            failed[part] = "; ".join(failures)
        else:
            covered[part] = "; ".join(failures)
    notes = [f"{part}: one solid hull around a hollow part ({why})" for part, why in failed.items()]
    notes += [f"{part}: boxes stand in ({why})" for part, why in covered.items()]
    message = "; ".join(notes) if notes else "every hollow part decomposed"
    return Finding("collision", "decomposition", not failed, message,
                   {"failures": {**covered, **failed}, "solid_blocks": sorted(failed)})
