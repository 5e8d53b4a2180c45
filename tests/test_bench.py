"""The bench runner end to end on two generated objects: scores, report, pictures."""

import json

from rest2art.bench import generated_items, run_items, write_report


def test_bench_run_writes_reports_with_pictures(tmp_path, config_file):
    items = generated_items(2, "asset", seed=31, kinds=("microwave", "box"))
    records = run_items(items, tmp_path, str(config_file), check=False, workers=1)
    assert [r.get("error") for r in records] == [None, None]
    report = write_report(records, tmp_path, "test")
    summary = json.loads((tmp_path / "results.json").read_text())["summary"]
    assert summary["type_accuracy_pct"] == 100.0 and summary["miou"] == 1.0
    html = (tmp_path / "report.html").read_text()
    for r in records:
        assert (tmp_path / r["picture"]).is_file() and r["picture"] in html
    assert "microwave_0031" in report.read_text()
