#!/usr/bin/env python3
"""CSV, tables and plots of the dev-machine scaling bench (bench/scaling_dev.sh).

  scaling_report.py init CSV                       start an empty CSV (header only)
  scaling_report.py add CSV [--stats F] [--info F] [--diff F] key=value ...
                                                   append one row (render --stats-json, info --json,
                                                   diff --json files are flattened into it)
  scaling_report.py report CSV --md FILE --plots DIR [--command ..] [--started ..] ...
                                                   write the markdown tables and the PNG plots

Every figure in the markdown and the plots is read from the CSV; nothing is typed by hand.
"""
import argparse
import csv
import json
import os
import platform
import sys
from collections import OrderedDict
from pathlib import Path

COLUMNS = [
    "kind", "requested_triangles", "triangles", "step", "label", "backend", "depth",
    "budget_bytes", "chunk_slots", "chunks_total", "wall_s", "peak_rss_bytes",
    "render_seconds", "build_seconds", "rays", "rays_per_second", "peak_host_bytes",
    "chunks_touched", "chunk_loads", "chunk_decodes", "stream_chunks_touched", "stream_reloads",
    "bytes_read", "bytes_uploaded", "decode_seconds", "upload_seconds", "device_seconds",
    "submits", "walk_passes", "host_to_device_bytes", "device_to_host_bytes", "peak_device_bytes",
    "memory_budget_bytes", "diff_against", "rmse", "psnr", "max_error", "primid_agreement",
    "generate_s", "generate_peak_rss_bytes", "ply_bytes", "parse_s", "package_s", "chunks",
    "file_bytes", "resident_bytes", "max_chunk_resident_bytes", "chunk_size_bytes",
    "duplicated_references", "chunk_size", "threads", "resolution", "spp", "host_cache", "image",
    "load1",
]
INFO_KEYS = ["triangles", "chunks", "file_bytes", "max_chunk_resident_bytes", "chunk_size_bytes",
             "duplicated_references"]
DIFF_KEYS = ["rmse", "psnr", "max_error", "primid_agreement"]
MiB, GiB = 2.0**20, 2.0**30


def cmd_init(args):
    with open(args.csv, "w", newline="") as f:
        csv.writer(f).writerow(COLUMNS)


def cmd_add(args):
    row = {}
    if args.stats:
        with open(args.stats) as f:
            row.update({k: v for k, v in json.load(f).items() if k in COLUMNS})
    if args.info:
        with open(args.info) as f:
            info = json.load(f)
        row.update({k: info[k] for k in INFO_KEYS if k in info})
        row["resident_bytes"] = sum(c["resident_bytes"] for c in info["chunk"])
    if args.diff:
        try:
            with open(args.diff) as f:
                diff = json.load(f)
            row.update({k: diff.get(k) for k in DIFF_KEYS if k in diff})
            if diff.get("psnr") is None and diff.get("rmse") == 0:
                row["psnr"] = "inf"
        except (OSError, ValueError):
            row["diff_against"] = "diff failed"
    for pair in args.pairs:
        key, _, value = pair.partition("=")
        if key not in COLUMNS:
            sys.exit(f"scaling_report.py: unknown column {key}")
        row[key] = value
    with open(args.csv, "a", newline="") as f:
        csv.DictWriter(f, COLUMNS).writerow({k: ("" if row.get(k) is None else row.get(k, "")) for k in COLUMNS})


def num(row, key, default=None):
    v = row.get(key, "")
    if v in ("", None):
        return default
    try:
        return float(v)
    except ValueError:
        return default


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def series_name(row):
    """Render rows -> 'embree', 'vulkan in core', 'vulkan out of core' (the label before the comma)."""
    return row["label"].split(",")[0]


def machine_line():
    cpu = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    ram = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / GiB
    distro = platform.system()
    try:
        for line in open("/etc/os-release"):
            if line.startswith("PRETTY_NAME="):
                distro = line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    return f"{os.cpu_count()} cores of {cpu}, {ram:.1f} GiB RAM, {distro}, kernel {platform.release()}"


def plot_all(rows, plots, depth_labels):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FormatStrFormatter, LogLocator

    plots.mkdir(parents=True, exist_ok=True)
    kinds = list(OrderedDict.fromkeys(r["kind"] for r in rows if r["step"] in ("import", "render")))
    many = len(kinds) > 1
    imports = [r for r in rows if r["step"] == "import"]
    renders = [r for r in rows if r["step"] == "render" and not r["label"].startswith("check")]
    written = []

    def loglog(ax, xlabel, ylabel, title):
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(FormatStrFormatter("%g"))
            axis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
            axis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.tick_params(which="minor", labelsize=6)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.set_title(title, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)

    def proportional(ax, xs, y0):
        """A dotted 'proportional to N' guide through the first point."""
        if len(xs) > 1 and y0:
            ax.plot([xs[0], xs[-1]], [y0, y0 * xs[-1] / xs[0]], ":", color="grey", label="∝ triangles")

    # Import: time and peak RSS against triangles.
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for kind in kinds:
        rs = sorted((r for r in imports if r["kind"] == kind), key=lambda r: num(r, "triangles"))
        if not rs:
            continue
        xs = [num(r, "triangles") / 1e6 for r in rs]
        tag = f"{kind}: " if many else ""
        a.plot(xs, [num(r, "wall_s") for r in rs], "o-", label=f"{tag}import wall")
        a.plot(xs, [num(r, "package_s") for r in rs], "s--", label=f"{tag}package stage")
        a.plot(xs, [num(r, "parse_s") for r in rs], "^--", label=f"{tag}PLY parse")
        b.plot(xs, [num(r, "peak_rss_bytes") / GiB for r in rs], "o-", label=f"{tag}import peak RSS")
        b.plot(xs, [num(r, "resident_bytes") / GiB for r in rs], "s--", label=f"{tag}scene resident size")
        b.plot(xs, [num(r, "file_bytes") / GiB for r in rs], "^--", label=f"{tag}package file")
        if kind == kinds[0]:
            proportional(a, xs, num(rs[0], "wall_s"))
    loglog(a, "triangles (millions)", "seconds", "vastray import (all cores)")
    loglog(b, "triangles (millions)", "GiB", "import peak RSS and sizes")
    fig.tight_layout()
    fig.savefig(plots / "import.png", dpi=110)
    plt.close(fig)
    written.append("import.png")

    # Render wall time against triangles, one panel per depth.
    names = list(OrderedDict.fromkeys(series_name(r) for r in renders))
    colour = {name: f"C{i}" for i, name in enumerate(names)}  # one colour per backend / budget
    depths = sorted({int(num(r, "depth")) for r in renders})
    if renders:
        fig, axes = plt.subplots(1, len(depths), figsize=(5 * len(depths), 4), squeeze=False)
        for ax, d in zip(axes[0], depths):
            for kind in kinds:
                for name in names:
                    rs = sorted((r for r in renders if r["kind"] == kind and series_name(r) == name
                                 and int(num(r, "depth")) == d), key=lambda r: num(r, "triangles"))
                    if not rs:
                        continue
                    xs = [num(r, "triangles") / 1e6 for r in rs]
                    ax.plot(xs, [num(r, "wall_s") for r in rs], "o-", color=colour[name],
                            label=(f"{kind}: " if many else "") + name)
            first = sorted((r for r in renders if int(num(r, "depth")) == d), key=lambda r: num(r, "triangles"))
            xs = sorted({num(r, "triangles") / 1e6 for r in first})
            if first:
                proportional(ax, xs, min(num(r, "wall_s") for r in first if num(r, "triangles") / 1e6 == xs[0]))
            loglog(ax, "triangles (millions)", "render wall time, s (process, load included)",
                   depth_labels.get(d, f"depth {d}"))
        fig.tight_layout()
        fig.savefig(plots / "render_time.png", dpi=110)
        plt.close(fig)
        written.append("render_time.png")

        # Peak RSS, chunk loads and bytes uploaded of the renders.
        fig, axes = plt.subplots(1, 3, figsize=(15, 4))
        panels = [("peak_rss_bytes", GiB, "peak RSS, GiB", "render peak RSS (process)", None),
                  ("chunk_loads", 1, "chunk loads", "chunk loads (vulkan)", "vulkan"),
                  ("bytes_uploaded", MiB, "MiB uploaded", "bytes uploaded to the device (vulkan)", "vulkan")]
        for ax, (key, scale, ylabel, title, only) in zip(axes, panels):
            for kind in kinds:
                for name in names:
                    for d in depths:
                        rs = sorted((r for r in renders if r["kind"] == kind and series_name(r) == name
                                     and int(num(r, "depth")) == d and (only is None or r["backend"] == only)),
                                    key=lambda r: num(r, "triangles"))
                        rs = [r for r in rs if num(r, key)]
                        if not rs:
                            continue
                        ax.plot([num(r, "triangles") / 1e6 for r in rs], [num(r, key) / scale for r in rs],
                                "o-" if d == 0 else "s--", color=colour[name],
                                label=(f"{kind}: " if many else "") + f"{name}, {depth_labels.get(d, d)}")
            loglog(ax, "triangles (millions)", ylabel, title)
        fig.tight_layout()
        fig.savefig(plots / "render_memory_io.png", dpi=110)
        plt.close(fig)
        written.append("render_memory_io.png")
    return written


def cmd_report(args):
    rows = read_rows(args.csv)
    imports = [r for r in rows if r["step"] == "import"]
    renders = [r for r in rows if r["step"] == "render"]
    depths = sorted({int(num(r, "depth")) for r in renders})
    depth_labels = {d: ("primary (depth 0)" if d == 0 else f"path depth {d}") for d in depths}
    plots = Path(args.plots)
    written = plot_all(rows, plots, depth_labels)
    md = Path(args.md)
    rel = os.path.relpath(plots, md.parent)
    first = dict(next((r for r in rows if r["step"] == "render"), {}))
    first["chunk_size"] = imports[0]["chunk_size"] if imports else "?"
    first["threads"] = imports[0]["threads"] if imports else "?"
    first["host_cache"] = next((r["host_cache"] for r in rows if r.get("backend") == "vulkan"), "?")
    startup = [num(r, "wall_s") for r in rows if r["step"] == "startup"]

    out = []
    w = out.append
    w(f"<!-- written by bench/scaling_report.py from {os.path.relpath(args.csv, md.parent)} "
      "(bench/scaling_dev.sh); do not edit by hand -->")
    w("# Scaling on the development machine: import, Embree, streaming in core and out of core")
    w("")
    w(f"Measured {args.started} to {args.finished} on {machine_line()}. Vulkan device: {args.device}.")
    w(f"Load average (1, 5, 15 min) {args.load_start} at the start and {args.load_end} at the end; the machine "
      "is shared with builds and other work, so expect ±10–20 % between runs (the `load1` column of the CSV "
      "has the 1-minute load average before each step).")
    w("")
    w(f"Command: `{args.command}`")
    w("")
    w(f"Every figure: [{os.path.basename(args.csv)}]({os.path.relpath(args.csv, md.parent)}). Scenes: "
      "`vastray generate KIND --triangles N --seed 1`, imported with "
      f"`--chunk-size {first.get('chunk_size', '?')}` (the import default is 16MiB), quantization and Draco "
      f"speed at their defaults, all {first.get('threads', '?')} cores. Renders of the package at "
      f"{first.get('resolution', '?')}, {first.get('spp', '?')} spp, seed 1, path integrator; *primary* is "
      "`--max-depth 0` (camera rays only), *path depth d* adds d bounces with shadow rays. Every render is a "
      "fresh process timed with `/usr/bin/time` (*wall s*, *peak RSS*: package open, chunk reads and decodes, "
      "Embree's BVH build, tracing, image write). *embree*: `--backend embree`, every chunk decoded, duplicated "
      "references removed, whole scene in core. *vulkan in core*: `--backend vulkan` with a `--memory-budget` "
      "of one slot per chunk plus the largest ray batch; *vulkan out of core*: a budget of the scene's resident "
      f"size / {args.ooc_fraction} (raised to the scene's minimum, one slot plus a minimal ray batch, when "
      f"below it); both with `--host-cache {first['host_cache']}` of decoded chunks "
      "in host memory (the render default). Embree's primary render also writes the primid AOV, the "
      "reference of the image check below.")
    if startup:
        w("")
        w(f"Process start-up alone (`vastray --version`, dynamic linking of OpenImageIO, Vulkan and Embree) took "
          f"{fmt(startup[0], '.2f')} s at the start of the run; it is part of every wall time below.")
    w("")
    w("## Import")
    w("")
    w("| scene | triangles | chunks | resident MiB | package MiB | package B/tri | PLY MiB | generate s "
      "| parse s | package stage s | import wall s | M tri/s (wall) | peak RSS GiB |")
    w("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in imports:
        t = num(r, "triangles")
        w(f"| {r['kind']} | {int(t):,} | {r['chunks']} | {fmt(num(r, 'resident_bytes') / MiB, '.1f')} "
          f"| {fmt(num(r, 'file_bytes') / MiB, '.1f')} | {fmt(num(r, 'file_bytes') / t, '.1f')} "
          f"| {fmt(num(r, 'ply_bytes', 0) / MiB, '.0f')} | {fmt(num(r, 'generate_s'), '.2f')} "
          f"| {fmt(num(r, 'parse_s'), '.2f')} | {fmt(num(r, 'package_s'), '.2f')} | {fmt(num(r, 'wall_s'), '.2f')} "
          f"| {fmt(t / num(r, 'wall_s') / 1e6, '.2f')} | {fmt(num(r, 'peak_rss_bytes') / GiB, '.2f')} |")
    w("")
    w("## Renders")
    w("")
    w("*slots* = chunk slots the budget gives / chunks in the package. *loads* = chunk uploads into a slot, "
      "*touched* = distinct chunks traced. *vs in core* and *vs Embree* divide the wall time by the in-core "
      "vulkan and by the Embree render of the same scene and depth. *image*: `vastray diff` against the "
      "image named (PSNR of the beauty; `inf` = identical).")
    w("")
    w("| scene | triangles | render | budget MiB | slots | wall s | render s | BVH build s | device s "
      "| decode s (workers) | upload s | loads / touched | MiB read | MiB uploaded | peak device MiB "
      "| peak RSS GiB | vs in core | vs Embree | image |")
    w("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")

    def ref(r, name):
        for x in renders:
            if (x["kind"], x["requested_triangles"], x["depth"]) == (r["kind"], r["requested_triangles"], r["depth"]) \
                    and x["label"].startswith(name) and not x["label"].startswith("check"):
                return num(x, "wall_s")
        return None

    checks = []
    for r in renders:
        if r["label"].startswith("check"):
            checks.append(r)
            continue
        vk = r["backend"] == "vulkan"
        slots = f"{r['chunk_slots']} / {r['chunks_total']}" if vk else "-"
        loads = f"{r['chunk_loads']} / {r['chunks_touched']}" if vk else "-"
        in_core, embree = ref(r, "vulkan in core"), ref(r, "embree")
        wall = num(r, "wall_s")
        image = "-"
        if r.get("diff_against"):
            psnr = r.get("psnr") or "-"
            image = f"{psnr if psnr == 'inf' else fmt(num(r, 'psnr'), '.1f') + ' dB'} vs {r['diff_against']}"
        w(f"| {r['kind']} | {int(num(r, 'triangles')):,} | {r['label']} "
          f"| {fmt(num(r, 'budget_bytes') / MiB, '.1f') if vk else '-'} | {slots} | {fmt(wall, '.2f')} "
          f"| {fmt(num(r, 'render_seconds'), '.2f')} | {fmt(num(r, 'build_seconds'), '.2f') if not vk else '-'} "
          f"| {fmt(num(r, 'device_seconds'), '.2f') if vk else '-'} | {fmt(num(r, 'decode_seconds'), '.2f') if vk else '-'} "
          f"| {fmt(num(r, 'upload_seconds'), '.3f') if vk else '-'} | {loads} "
          f"| {fmt(num(r, 'bytes_read', 0) / MiB, '.1f') if vk else '-'} "
          f"| {fmt(num(r, 'bytes_uploaded', 0) / MiB, '.1f') if vk else '-'} "
          f"| {fmt(num(r, 'peak_device_bytes', 0) / MiB, '.1f') if vk else '-'} "
          f"| {fmt(num(r, 'peak_rss_bytes') / GiB, '.2f')} "
          f"| {fmt(wall / in_core, '.2f') + 'x' if vk and in_core else '-'} "
          f"| {fmt(wall / embree, '.2f') + 'x' if embree else '-'} | {image} |")
    w("")
    w("## Summary: wall time ratios")
    w("")
    w("| scene | triangles | " + " | ".join(
        f"{lab}: out of core / in core | {lab}: in core / Embree | {lab}: out of core / Embree"
        for lab in (depth_labels[d] for d in depths)) + " |")
    w("|---|---|" + "---|" * (3 * len(depths)))
    for imp in imports:
        cells = []
        for d in depths:
            key = (imp["kind"], imp["requested_triangles"], str(d))

            def wall_of(name):
                for x in renders:
                    if (x["kind"], x["requested_triangles"], x["depth"]) == key and x["label"].startswith(name):
                        return num(x, "wall_s")
                return None

            e, i, o = wall_of("embree"), wall_of("vulkan in core"), wall_of("vulkan out of core")
            cells += [fmt(o / i if o and i else None, ".2f"), fmt(i / e if i and e else None, ".2f"),
                      fmt(o / e if o and e else None, ".2f")]
        w(f"| {imp['kind']} | {int(num(imp, 'triangles')):,} | " + " | ".join(cells) + " |")
    if checks:
        w("")
        w("## Image check: primitive ids against Embree")
        w("")
        w("The streaming renderer's primid AOV against Embree's, at the out-of-core budget (a separate render: "
          "the AOV adds a pixel-centre ray stream, so it is not in the timed rows).")
        w("")
        w("| scene | triangles | render | primid agreement | beauty PSNR | beauty max error | wall s |")
        w("|---|---|---|---|---|---|---|")
        for r in checks:
            agree = num(r, "primid_agreement")
            psnr = r.get("psnr") or "-"
            w(f"| {r['kind']} | {int(num(r, 'triangles')):,} | {r['label'].removeprefix('check: ')} "
              f"| {fmt(100 * agree if agree is not None else None, '.4f')} % "
              f"| {psnr if psnr in ('inf', '-') else fmt(num(r, 'psnr'), '.1f') + ' dB'} "
              f"| {fmt(num(r, 'max_error'), '.3g')} | {fmt(num(r, 'wall_s'), '.2f')} |")
    w("")
    w("## Plots")
    w("")
    for name in written:
        w(f"![{name}]({rel}/{name})")
        w("")
    md.parent.mkdir(parents=True, exist_ok=True)
    md.write_text("\n".join(out))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("init")
    s.add_argument("csv")
    s = sub.add_parser("add")
    s.add_argument("csv")
    s.add_argument("--stats")
    s.add_argument("--info")
    s.add_argument("--diff")
    s = sub.add_parser("report")
    s.add_argument("csv")
    s.add_argument("--md", required=True)
    s.add_argument("--plots", required=True)
    s.add_argument("--command", default="?")
    s.add_argument("--started", default="?")
    s.add_argument("--finished", default="?")
    s.add_argument("--load-start", default="?")
    s.add_argument("--load-end", default="?")
    s.add_argument("--device", default="?")
    s.add_argument("--ooc-fraction", default="4")
    # key=value pairs of `add` are left over by argparse (a '*' positional after options does not parse).
    args, rest = p.parse_known_args()
    if args.cmd == "add":
        args.pairs = rest
    elif rest:
        p.error("unrecognized arguments: " + " ".join(rest))
    {"init": cmd_init, "add": cmd_add, "report": cmd_report}[args.cmd](args)


if __name__ == "__main__":
    main()
