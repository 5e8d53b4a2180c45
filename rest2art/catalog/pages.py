"""The catalog a person browses: ``index.html`` (a thumbnail grid with filters by outcome and
category) and ``pages/NAME.html`` per object (closed and opened pictures, an animation per joint,
the joint table, the validation table, refinements and reasons). Static HTML with relative
links, written from the index and the entries' ``validation.json``.
"""

from __future__ import annotations

import html
import json
import os
from collections import Counter
from pathlib import Path

from rest2art.catalog.records import OUTCOMES
from rest2art.catalog.store import entry_folder, latest_records, read_index

PAGES = "pages"
STYLE = """
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}
h1{margin:0 0 .3em}.filters{margin:1em 0;display:flex;gap:1.5em;flex-wrap:wrap;align-items:center}
.grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(250px,1fr));gap:12px}
.card{border:1px solid #ddd;border-radius:6px;padding:6px;background:#fff}
.card img{width:100%;display:block}.card .blank{height:120px;display:flex;align-items:center;
justify-content:center;background:#f4f4f4;color:#777;font-size:.9em;text-align:center;padding:4px}
.name{font-weight:600;word-break:break-all}.meta{font-size:.85em;color:#555}
.badge{display:inline-block;padding:0 6px;border-radius:8px;font-size:.8em;color:#fff}
.published{background:#2e7d32}.rejected{background:#c62828}.static{background:#6d6d6d}.failed{background:#ef6c00}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:3px 8px;font-size:.9em}
.pass{color:#2e7d32}.fail{color:#c62828}.anims{display:flex;flex-wrap:wrap;gap:12px}
figure{margin:0}figcaption{font-size:.85em;text-align:center}
"""
FILTER_JS = """
function applyFilters(){
  const outcomes=[...document.querySelectorAll('input[name=outcome]:checked')].map(e=>e.value);
  const category=document.getElementById('category').value;
  let shown=0;
  document.querySelectorAll('.card').forEach(c=>{
    const ok=outcomes.includes(c.dataset.outcome)&&(category===''||c.dataset.category===category);
    c.style.display=ok?'':'none'; shown+=ok;});
  document.getElementById('shown').textContent=shown;
}
document.querySelectorAll('input,select').forEach(e=>e.addEventListener('change',applyFilters));
applyFilters();
"""
e = html.escape


def _write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(text)
    tmp.replace(path)


def _head(title: str) -> str:
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>{e(title)}</title>"
            f"<style>{STYLE}</style></head><body>")


def _card(record: dict) -> str:
    name, outcome = record["name"], record["outcome"]
    category = record.get("category") or "unknown"
    thumb = record.get("pictures", {}).get("thumbnail")
    if thumb and record.get("path"):
        picture = f"<img src='{e(record['path'])}/{e(thumb)}' alt='{e(name)}'>"
    else:
        picture = f"<div class='blank'>{e(record.get('error') or outcome)}</div>"
    joints = ", ".join(f"{n} {t}" for t, n in record.get("joints", {}).items()) or "no joints"
    return (f"<div class='card' data-outcome='{e(outcome)}' data-category='{e(category)}'>"
            f"<a href='{PAGES}/{e(name)}.html'>{picture}</a><div class='name'><a href='{PAGES}/{e(name)}.html'>"
            f"{e(name)}</a></div><div class='meta'><span class='badge {e(outcome)}'>{e(outcome)}</span> "
            f"{e(category)} · {e(joints)}</div></div>")


def index_page(records: list[dict]) -> str:
    """HTML of the catalog's front page for the latest record of each object."""
    counts = Counter(r["outcome"] for r in records)
    categories = sorted({r.get("category") or "unknown" for r in records})
    parts = [_head("rest2art catalog"), "<h1>rest2art catalog</h1>",
             "<div class='meta'>" + " · ".join(f"{counts.get(o, 0)} {o}" for o in OUTCOMES)
             + " · <span id='shown'></span> shown</div><div class='filters'><span>outcome:</span>"]
    parts += [f"<label><input type='checkbox' name='outcome' value='{o}' checked> {o} ({counts.get(o, 0)})</label>"
              for o in OUTCOMES]
    parts.append("<label>category: <select id='category'><option value=''>all</option>"
                 + "".join(f"<option value='{e(c)}'>{e(c)}</option>" for c in categories) + "</select></label></div>")
    parts.append("<div class='grid'>" + "".join(_card(r) for r in records) + "</div>")
    parts.append(f"<script>{FILTER_JS}</script></body></html>")
    return "\n".join(parts)


def _table(header: list[str], rows: list[list[str]]) -> str:
    return ("<table><tr>" + "".join(f"<th>{e(h)}</th>" for h in header) + "</tr>"
            + "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in rows) + "</table>")


def asset_page(record: dict, validation: dict | None) -> str:
    """HTML of one object's page; ``validation`` is its validation.json (None if it has none).
    Links are relative to ``pages/``."""
    name, outcome = record["name"], record["outcome"]
    base = f"../{record['path']}/" if record.get("path") else ""
    pictures = record.get("pictures", {})
    parts = [_head(name), "<p><a href='../index.html'>&larr; catalog</a></p>",
             f"<h1>{e(name)} <span class='badge {e(outcome)}'>{e(outcome)}</span></h1>",
             f"<div class='meta'>category {e(record.get('category') or 'unknown')} · source {e(record['source'])}"
             f" · key {e(record['key'][:16])}</div>"]
    if record.get("error"):
        parts.append(f"<h2>Error</h2><pre>{e(record['error'])}</pre>")
    if record.get("log_tail"):
        parts.append(f"<h3>End of the worker's output</h3><pre>{e(record['log_tail'])}</pre>")
    gate_findings = (record.get("gate") or {}).get("findings", [])
    if gate_findings:
        parts.append("<h2>Plausibility gate</h2>" + _table(["finding", "parts", "action", "detail"], [
            [e(f["kind"]), e(", ".join(f["parts"])), e(f["action"]), e(f["message"])] for f in gate_findings]))
    if "closed" in pictures:
        parts.append("<h2>Closed and opened</h2><div class='anims'>"
                     f"<figure><img src='{e(base + pictures['closed'])}' alt='closed'><figcaption>closed</figcaption>"
                     "</figure>"
                     f"<figure><img src='{e(base + pictures['opened'])}' alt='opened'><figcaption>opened</figcaption>"
                     "</figure></div>")
    elif "thumbnail" in pictures:
        parts.append(f"<h2>Closed and opened</h2><img src='{e(base + pictures['thumbnail'])}' alt='thumbnail'>")
    joints = record.get("joint_table", [])
    anims = [(j["name"], pictures[j["name"]]) for j in joints if j["name"] in pictures]
    if anims:
        parts.append("<h2>Joints in motion</h2><div class='anims'>" + "".join(
            f"<figure><img class='anim' src='{e(base + path)}' alt='{e(joint)}'><figcaption>{e(joint)}</figcaption>"
            "</figure>" for joint, path in anims) + "</div>")
    if joints:
        rows = [[e(j["name"]), e(j["type"]), e(j["parent"]), e(j["child"]), e(str(j["axis"])), e(str(j["origin"])),
                 e(str(j["limit"]))] for j in joints]
        parts.append("<h2>Joints</h2>" + _table(["joint", "type", "parent", "child", "axis", "origin", "limit"], rows))
    if record.get("urdf"):
        parts.append(f"<p>files: <a href='{e(base + record['urdf'])}'>{e(record['urdf'])}</a> · "
                     f"<a href='{e(base + record['mjcf'])}'>{e(record['mjcf'])}</a></p>")
    summary = record.get("validation")
    if summary:
        parts.append(f"<h2>Validation: {e(summary['decision'])}</h2>")
        if summary["refinements"]:
            parts.append("<h3>Refinements</h3>" + _table(["done", "why"], [[e(r["done"]), e(r["why"])]
                                                                           for r in summary["refinements"]]))
        if summary["reasons"]:
            parts.append("<h3>Reasons</h3><ul>" + "".join(f"<li>{e(r)}</li>" for r in summary["reasons"]) + "</ul>")
    if validation and validation.get("rounds"):
        findings = validation["rounds"][-1]["findings"]
        rows = [[e(f["check"]), e(f["subject"]), "<span class='pass'>pass</span>" if f["ok"]
                 else "<span class='fail'>FAIL</span>", e(f["message"])] for f in findings]
        parts.append("<h3>Checks (last round)</h3>" + _table(["check", "subject", "result", "detail"], rows))
    timings = record.get("timings", {})
    if timings:
        parts.append("<h2>Timings</h2>" + _table(["stage", "seconds"], [[e(k), f"{v:.2f}"] for k, v in {
            **timings.get("stages", {}), **{k: v for k, v in timings.items() if k != "stages"}}.items()]))
    parts.append("</body></html>")
    return "\n".join(parts)


def write_site(root: str | Path) -> Path:
    """(Re)write ``index.html`` and every ``pages/NAME.html`` of the catalog at ``root`` from its
    index; pages of names no longer in it are removed. Returns the index.html path."""
    root = Path(root)
    records = list(latest_records(read_index(root)).values())
    pages = root / PAGES
    pages.mkdir(parents=True, exist_ok=True)
    for record in records:
        folder = entry_folder(root, record)
        path = folder / "validation.json" if folder is not None else None
        validation = json.loads(path.read_text()) if path is not None and path.is_file() else None
        _write(pages / f"{record['name']}.html", asset_page(record, validation))
    names = {f"{r['name']}.html" for r in records}
    for stale in pages.glob("*.html"):
        if stale.name not in names:
            stale.unlink()
    _write(root / "index.html", index_page(records))
    return root / "index.html"
