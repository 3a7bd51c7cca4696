"""summary.json and report.html of a check (and the merge of shard summaries)."""
import html
import json
import os

STATUS_ORDER = {"error": 0, "fail": 1, "missing": 2, "pass": 3}


def exit_status(cases):
    """0 every case passed; 1 a case failed or has no reference; 3 a capture or comparison failed to run."""
    statuses = {c["status"] for c in cases}
    if "error" in statuses:
        return 3
    if statuses & {"fail", "missing"}:
        return 1
    return 0


def summary(suite, cases, shard=None):
    counts = {}
    for c in cases:
        counts[c["status"]] = counts.get(c["status"], 0) + 1
    return {"suite": suite["name"], "suite_file": suite["path"], "references": suite["references"], "shard": shard,
            "counts": counts, "exit_status": exit_status(cases), "cases": cases}


def without_timings(value):
    """The summary without its wall-clock figures (keys ending in 'seconds'): what two runs must share."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if not k.endswith("seconds")}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def write(out_dir, data, name="summary.json"):
    with open(os.path.join(out_dir, name), "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
    if name == "summary.json":
        with open(os.path.join(out_dir, "report.html"), "w") as f:
            f.write(render_html(data))


def _figures(frame):
    fig = frame.get("figures") or {}
    parts = []
    if "noise" in fig:
        n = fig["noise"]
        parts.append(f"noise: {n['failed_pixels']}/{n['pixels']} pixels beyond |z| {n['z_threshold']:.2f} "
                     f"(pass {100 * n['pass_fraction']:.2f} %, need {100 * n['min_pass_fraction']:.2f} %), mean |z| {n['mean_abs_z']:.2f}")
        for s in n.get("tile_scales", []):
            parts.append(f"{s['failed_tiles']}/{s['tiles']} {str(s['tile']) + 'x' + str(s['tile']) + ' tiles' if s['tile'] else 'whole image'}"
                         f" beyond |z| {s['z_threshold']:.2f} (max {s['max_abs_z']:.1f})")
    if "flip_mean" in fig:
        parts.append(f"FLIP mean {fig['flip_mean']:.4f}, max {fig['flip_max']:.3f}, "
                     f"{100 * fig['flip_fail_fraction']:.2f} % above {fig['flip_threshold']}")
        parts.append(f"PSNR {fig['psnr']:.2f} dB, SSIM {fig['ssim']:.4f}, identical: {'yes' if fig['identical'] else 'no'}")
    for reason in fig.get("reasons", []):
        parts.append("<b>" + html.escape(reason) + "</b>")
    return "<br>".join(p if p.startswith("<b>") else html.escape(p) for p in parts)


def render_html(data):
    cases = data["cases"]
    rows = []
    for c in cases:
        frames_html = []
        for fr in c.get("frames", []):
            img = fr.get("images", {})
            cells = []
            for key, label in (("new", "new (hover: reference)"), ("ref", "reference"), ("diff", "diff x16"),
                               ("heat", "error heat map")):
                if key not in img:
                    cells.append(f"<td class=img><div class=lbl>{label}</div><div class=none>-</div></td>")
                    continue
                src = html.escape(img[key])
                swap = ""
                if key == "new" and "ref" in img:
                    ref = html.escape(img["ref"])
                    swap = f" onmouseover=\"this.src='{ref}'\" onmouseout=\"this.src='{src}'\""
                cells.append(f"<td class=img><div class=lbl>{label}</div><img src=\"{src}\"{swap}></td>")
            frames_html.append(f"<tr><td class=fr><b>{html.escape(fr['name'])}</b> <span class={fr['status']}>"
                               f"{fr['status']}</span><br>{_figures(fr)}</td>{''.join(cells)}</tr>")
        message = html.escape(c.get("message", ""))
        rows.append(
            f"<tbody class=case data-name=\"{html.escape(c['name'])}\" data-error=\"{c.get('error_score', 0):.6g}\" "
            f"data-status=\"{STATUS_ORDER.get(c['status'], 9)}\"><tr><th colspan=5>{html.escape(c['name'])} "
            f"<span class={c['status']}>{c['status']}</span> <small>{html.escape(c.get('kind', ''))} / "
            f"{html.escape(c.get('renderer', ''))} / {html.escape(c.get('mode', ''))}"
            f"{' against ' + html.escape(c['against']) if c.get('against') else ''} / error score "
            f"{c.get('error_score', 0):.3g}{' / reference updated' if c.get('updated') else ''}</small>"
            f"{'<br>' + message if message else ''}</th></tr>{''.join(frames_html)}</tbody>")
    counts = ", ".join(f"{v} {k}" for k, v in sorted(data["counts"].items()))
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>pa-regress: {html.escape(data['suite'])}</title>
<style>
body {{ font: 13px sans-serif; margin: 1em; }}
table {{ border-collapse: collapse; }}
th {{ text-align: left; background: #eee; padding: 6px; }}
td {{ padding: 4px; vertical-align: top; }}
td.fr {{ width: 22em; }}
td.img img {{ width: 256px; image-rendering: pixelated; border: 1px solid #999; }}
.lbl {{ color: #666; font-size: 11px; }}
.pass {{ color: #070; font-weight: bold; }} .fail, .error {{ color: #b00; font-weight: bold; }}
.missing {{ color: #a60; font-weight: bold; }}
</style></head><body>
<h1>pa-regress: {html.escape(data['suite'])}</h1>
<p>{counts}; exit status {data['exit_status']}. References: {html.escape(data['references'])}.
Sort: <button onclick="sortBy('error')">by error</button> <button onclick="sortBy('name')">by name</button>
<button onclick="sortBy('status')">by status</button>. Hover a new image to see its reference.</p>
<table id=cases>{''.join(rows)}</table>
<script>
function sortBy(key) {{
  const table = document.getElementById('cases');
  const bodies = Array.from(table.tBodies);
  bodies.sort((a, b) => key === 'name' ? a.dataset.name.localeCompare(b.dataset.name)
                      : key === 'status' ? a.dataset.status - b.dataset.status
                      : parseFloat(b.dataset.error) - parseFloat(a.dataset.error));
  bodies.forEach(b => table.appendChild(b));
}}
sortBy('error');
</script></body></html>
"""
