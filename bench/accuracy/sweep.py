#!/usr/bin/env python3
"""Time against error: streaming (vulkan) renders swept over spp, quantization, memory budget and
chunk size, each compared with a high-sample Embree reference of the lossless scene.

Writes the CSVs under docs/generated/accuracy/ (see bench/accuracy/run.sh for the knobs). Every
figure comes from `vastray render --stats-json`, `vastray diff --json` or the pixels themselves.
"""
import csv
import hashlib
import json
import math
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

from imagedata import Image, primid_agreement, relative_mse, rmse
from poolplan import budget_for_slots, parse_minimum_bytes

DEFAULT_CHUNK = "16MiB"
DEFAULT_BITS = 20
AMPLE_BUDGET = "1GiB"

POINT_FIELDS = [
    "sweep", "scene", "curve", "spp", "quantize_bits", "chunk_size", "host_cache",
    "memory_budget_bytes", "chunks_total", "chunk_slots", "oversubscription", "render_seconds",
    "wall_seconds", "device_seconds", "decode_seconds", "upload_seconds", "rays", "chunk_loads",
    "chunks_touched", "bytes_read", "peak_device_bytes", "package_bytes", "rmse", "relmse",
    "primid_agreement", "paired_rmse", "paired_relmse",
]


def env_list(name, default):
    return os.environ.get(name, default).split()


class Config:
    def __init__(self, build):
        self.vastray = str(Path(build) / "vastray")
        self.work = Path(os.environ.get("WORK_DIR", str(Path(build) / "bench-accuracy")))
        self.out = Path(os.environ.get("OUT_DIR", "docs/generated/accuracy"))
        self.resolution = os.environ.get("RES", "160x120")
        self.max_depth = os.environ.get("MAX_DEPTH", "5")
        self.seed = os.environ.get("SEED", "0")
        self.ref_seed = os.environ.get("REF_SEED", "1")  # independent of the sweep's samples
        self.ref_spp = os.environ.get("REF_SPP", "4096")
        self.mesh_dir = Path(os.environ.get("MESH_DIR", "../shared/data/meshes"))
        self.gen_kinds = env_list("GEN_KINDS", "terrain soup city")
        self.gen_triangles = os.environ.get("GEN_TRIANGLES", "200000")
        self.full = os.environ.get("FULL", "0") == "1"
        self.full_triangles = os.environ.get("FULL_TRIANGLES", "10000000")
        self.full_ref_spp = os.environ.get("FULL_REF_SPP", "256")
        self.spp_list = env_list("SPP_LIST", "1 2 4 8 16")
        self.spp_extra_scenes = env_list("SPP_EXTRA_SCENES", "terrain")  # these also get SPP_EXTRA
        self.spp_extra = env_list("SPP_EXTRA", "32 64")
        self.full_spp_list = env_list("FULL_SPP_LIST", "1 4")
        self.quant_scenes = env_list("QUANT_SCENES", "stanford-bunny terrain")
        self.quant_list = env_list("QUANT_LIST", "14 16 18 20 24 0")
        self.quant_spp = env_list("QUANT_SPP", "1 8")
        self.budget_scenes = env_list("BUDGET_SCENES", "terrain city")
        self.budget_chunk = os.environ.get("BUDGET_CHUNK", "256KiB")
        self.budget_factors = env_list("BUDGET_FACTORS", "1 2 4 8 16")
        self.budget_spp = env_list("BUDGET_SPP", "1 4")
        self.budget_host_cache = os.environ.get("BUDGET_HOST_CACHE", "0")
        self.chunk_scenes = env_list("CHUNK_SCENES", "terrain city")
        self.chunk_list = env_list("CHUNK_LIST", "128KiB 512KiB 2MiB 16MiB")
        self.chunk_spp = env_list("CHUNK_SPP", "1 4")
        self.only_scenes = env_list("SCENES", "")


def run(cmd, log):
    """Runs a vastray command; a failure stops the sweep with the command and its output."""
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + f"\n# rc={p.returncode} wall={wall:.2f}s\n{p.stdout}{p.stderr}\n")
    if p.returncode != 0:
        sys.exit(f"bench-accuracy: command failed (rc {p.returncode}): {' '.join(cmd)}\n{p.stdout}{p.stderr}")
    return p, wall


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


class Bench:
    def __init__(self, cfg):
        self.cfg = cfg
        self.log = cfg.work / "commands.log"
        for d in ("scenes", "packages", "refs", "renders"):
            (cfg.work / d).mkdir(parents=True, exist_ok=True)
        self.rgb_cache = {}
        self.scene_rows, self.ref_rows, self.points, self.crosschecks = [], [], [], []
        self.packages = {}

    def vastray(self, *args):
        return run([self.cfg.vastray, *args], self.log)

    # Scenes and packages.
    def scenes(self):
        cfg, found = self.cfg, []
        if cfg.mesh_dir.is_dir():
            found += [(p.stem, p) for p in sorted(cfg.mesh_dir.glob("*.obj"))]
        else:
            print(f"bench-accuracy: {cfg.mesh_dir} absent, shared meshes skipped")
        for kind in cfg.gen_kinds:
            found.append((kind, self.generate(kind, cfg.gen_triangles)))
        if cfg.full:
            found.append(("city-full", self.generate("city", cfg.full_triangles)))
        if cfg.only_scenes:
            found = [s for s in found if s[0] in cfg.only_scenes]
        return found

    def generate(self, kind, triangles):
        ply = self.cfg.work / "scenes" / f"{kind}-{triangles}.ply"
        if not ply.exists():
            self.vastray("generate", kind, "--triangles", triangles, "--seed", "1", "-o", str(ply))
        return ply

    def package(self, name, source, bits=DEFAULT_BITS, chunk=DEFAULT_CHUNK):
        key = (name, str(bits), chunk)
        if key in self.packages:
            return self.packages[key]
        vast = self.cfg.work / "packages" / f"{name}-q{bits}-{chunk}.vast"
        self.vastray("import", str(source), "-o", str(vast), "--quantize-bits", str(bits),
                     "--chunk-size", chunk, "--progress", "none")
        info = json.loads(self.vastray("info", str(vast), "--json")[0].stdout)
        pkg = {"path": vast, "info": info, "bytes": vast.stat().st_size}
        self.packages[key] = pkg
        return pkg

    # Images.
    def rgb(self, exr):
        if exr not in self.rgb_cache:
            self.rgb_cache[exr] = Image(exr)
        return self.rgb_cache[exr]

    def embree(self, pkg, spp, seed):
        """An Embree render of `pkg`, cached by the package's content hash and the options."""
        cfg = self.cfg
        options = {"backend": "embree", "spp": spp, "seed": seed, "resolution": cfg.resolution,
                   "max_depth": cfg.max_depth, "integrator": "path", "aovs": "primid"}
        key = hashlib.sha256((sha256_file(pkg["path"]) + json.dumps(options, sort_keys=True)).encode()).hexdigest()[:24]
        exr, stats = cfg.work / "refs" / f"{key}.exr", cfg.work / "refs" / f"{key}.json"
        cached = exr.exists() and stats.exists()
        if not cached:
            self.vastray("render", str(pkg["path"]), "-o", str(exr), "--backend", "embree", "--spp", spp,
                         "--seed", seed, "--resolution", cfg.resolution, "--max-depth", cfg.max_depth,
                         "--aovs", "primid", "--stats-json", str(stats), "--progress", "none")
        return str(exr), json.loads(stats.read_text()), key, cached

    def reference(self, name, lossless):
        cfg = self.cfg
        spp = cfg.full_ref_spp if name == "city-full" else cfg.ref_spp
        exr, stats, key, cached = self.embree(lossless, spp, cfg.ref_seed)
        self.ref_rows.append({"scene": name, "spp": spp, "seed": cfg.ref_seed, "key": key,
                              "cached": int(cached), "render_seconds": f"{stats['render_seconds']:.3f}",
                              "rays": stats["rays"]})
        return exr

    def diff(self, a, b):
        return json.loads(self.vastray("diff", a, b, "--json")[0].stdout)

    # One sweep point: a streaming render, its figures and its errors.
    def point(self, sweep, scene, curve, pkg, spp, ref_exr, lossless, budget=AMPLE_BUDGET,
              host_cache="1GiB", bits=DEFAULT_BITS, chunk=DEFAULT_CHUNK):
        cfg = self.cfg
        stem = f"{sweep}-{scene}-{curve}-spp{spp}".replace("/", "_")
        exr = str(cfg.work / "renders" / f"{stem}.exr")
        stats_path = cfg.work / "renders" / f"{stem}.json"
        _, wall = self.vastray("render", str(pkg["path"]), "-o", exr, "--backend", "vulkan", "--spp", spp,
                               "--seed", cfg.seed, "--resolution", cfg.resolution, "--max-depth", cfg.max_depth,
                               "--memory-budget", str(budget), "--host-cache", host_cache, "--aovs", "primid",
                               "--stats-json", str(stats_path), "--progress", "none")
        st = json.loads(stats_path.read_text())
        img, ref = Image(exr), self.rgb(ref_exr)
        paired = self.rgb(self.embree(lossless, spp, cfg.seed)[0])
        self.crosscheck(scene, exr, ref_exr, img, ref)
        self.points.append({
            "sweep": sweep, "scene": scene, "curve": curve, "spp": spp, "quantize_bits": bits,
            "chunk_size": chunk, "host_cache": host_cache, "memory_budget_bytes": st["memory_budget_bytes"],
            "chunks_total": st["chunks_total"], "chunk_slots": st["chunk_slots"],
            "oversubscription": f"{st['chunks_total'] / st['chunk_slots']:.3f}",
            "render_seconds": f"{st['render_seconds']:.3f}", "wall_seconds": f"{wall:.3f}",
            "device_seconds": f"{st['device_seconds']:.3f}", "decode_seconds": f"{st['decode_seconds']:.3f}",
            "upload_seconds": f"{st['upload_seconds']:.3f}", "rays": st["rays"], "chunk_loads": st["chunk_loads"],
            "chunks_touched": st["chunks_touched"], "bytes_read": st["bytes_read"],
            "peak_device_bytes": st["peak_device_bytes"], "package_bytes": pkg["bytes"],
            "rmse": f"{rmse(img, ref):.6g}", "relmse": f"{relative_mse(img, ref):.6g}",
            "primid_agreement": f"{primid_agreement(img, ref):.6f}",
            "paired_rmse": f"{rmse(img, paired):.6g}", "paired_relmse": f"{relative_mse(img, paired):.6g}",
        })
        p = self.points[-1]
        print(f"  {sweep:6} {scene:15} {curve:12} spp {spp:>4}: {p['render_seconds']:>8} s  rmse {p['rmse']:>10}"
              f"  relmse {p['relmse']:>10}  primid {p['primid_agreement']}  paired rmse {p['paired_rmse']}", flush=True)

    def crosscheck(self, scene, exr, ref_exr, img, ref):
        """The bench's EXR reader must agree with `vastray diff` (once per scene: each diff costs
        a process start)."""
        if any(c["scene"] == scene for c in self.crosschecks):
            return
        d = self.diff(exr, ref_exr)
        ours, agree = rmse(img, ref), primid_agreement(img, ref)
        self.crosschecks.append({"scene": scene, "vastray_diff_rmse": d["rmse"], "bench_rmse": ours,
                                 "vastray_diff_primid": d["primid_agreement"], "bench_primid": agree})
        # float32 pixels summed in float64 here and in OIIO: they agree to far better than 1e-6.
        if abs(ours - d["rmse"]) > 1e-6 * max(1.0, d["rmse"]) or abs(agree - d["primid_agreement"]) > 1e-9:
            sys.exit(f"bench-accuracy: EXR reader disagrees with vastray diff on {scene}: rmse {ours} vs "
                     f"{d['rmse']}, primid {agree} vs {d['primid_agreement']}")

    # The sweeps.
    def sweep_scene(self, name, source):
        cfg = self.cfg
        lossless = self.package(name, source, bits=0)
        default = self.package(name, source)
        ref = self.reference(name, lossless)
        self.scene_rows.append({"scene": name, "source": source.name, "triangles": lossless["info"]["triangles"],
                                "lossless_package_bytes": lossless["bytes"], "default_package_bytes": default["bytes"],
                                "default_chunks": default["info"]["chunks"]})
        spps = cfg.full_spp_list if name == "city-full" else cfg.spp_list
        for spp in spps + (cfg.spp_extra if name in cfg.spp_extra_scenes else []):
            self.point("spp", name, "default", default, spp, ref, lossless)
        if name in cfg.quant_scenes:
            for bits in cfg.quant_list:
                pkg = self.package(name, source, bits=int(bits))
                curve = "lossless" if bits == "0" else f"{bits} bits"
                for spp in cfg.quant_spp:
                    self.point("quant", name, curve, pkg, spp, ref, lossless, bits=int(bits))
        if name in cfg.budget_scenes:
            self.budget_sweep(name, source, ref, lossless)
        if name in cfg.chunk_scenes:
            for chunk in cfg.chunk_list:
                pkg = self.package(name, source, chunk=chunk)
                for spp in cfg.chunk_spp:
                    self.point("chunk", name, chunk, pkg, spp, ref, lossless, chunk=chunk)

    def budget_sweep(self, name, source, ref, lossless):
        cfg = self.cfg
        pkg = self.package(name, source, chunk=cfg.budget_chunk)
        chunks = pkg["info"]["chunks"]
        minimum = self.probe_minimum(pkg)
        for factor in cfg.budget_factors:
            slots = max(1, math.ceil(chunks / float(factor)))
            budget = budget_for_slots(minimum, chunks, slots)
            for spp in cfg.budget_spp:
                self.point("budget", name, f"{factor}x", pkg, spp, ref, lossless, budget=budget,
                           host_cache=cfg.budget_host_cache, chunk=cfg.budget_chunk)
                got = self.points[-1]["chunk_slots"]
                if got != slots:
                    print(f"bench-accuracy: warning: asked for {slots} slots with {budget} bytes, the renderer made {got}"
                          " (bench/accuracy/poolplan.py no longer mirrors planPool?)", flush=True)

    def probe_minimum(self, pkg):
        """The scene's smallest budget, as the renderer states it when given too little. The AOVs
        must be the sweep's: the primid AOV makes every chunk slot larger."""
        cmd = [self.cfg.vastray, "render", str(pkg["path"]), "-o", str(self.cfg.work / "renders" / "probe.exr"),
               "--backend", "vulkan", "--spp", "1", "--resolution", "8x8", "--memory-budget", "1024",
               "--aovs", "primid", "--progress", "none"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        minimum = parse_minimum_bytes(p.stdout + p.stderr)
        if p.returncode == 0 or minimum is None:
            sys.exit(f"bench-accuracy: expected a minimum-budget error from: {' '.join(cmd)}\n{p.stdout}{p.stderr}")
        return minimum


def write_csv(path, rows, fields=None):
    fields = fields or (list(rows[0].keys()) if rows else [])
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)


def machine():
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    mem = next((int(l.split()[1]) for l in open("/proc/meminfo") if l.startswith("MemTotal")), 0)
    return f"{os.cpu_count()} cores of {cpu}, {mem / 2**20:.0f} GiB RAM, {platform.system()} {platform.release()}"


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    cfg = Config(build)
    bench = Bench(cfg)
    started, t0 = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), time.monotonic()
    for name, source in bench.scenes():
        print(f"bench-accuracy: {name} ({source})", flush=True)
        bench.sweep_scene(name, source)
    cfg.out.mkdir(parents=True, exist_ok=True)
    write_csv(cfg.out / "points.csv", bench.points, POINT_FIELDS)
    write_csv(cfg.out / "scenes.csv", bench.scene_rows)
    write_csv(cfg.out / "references.csv", bench.ref_rows)
    settings = {k: v for k, v in vars(cfg).items() if k not in ("vastray", "work", "out")}
    run_info = {"started": started, "wall_seconds": round(time.monotonic() - t0, 1), "machine": machine(),
                "vulkan_device": vulkan_device(cfg.work / "commands.log"),
                "command": os.environ.get("BENCH_COMMAND", "bash bench/accuracy/run.sh " + build),
                "settings": {k: (str(v) if isinstance(v, Path) else v) for k, v in settings.items()},
                "rmse_crosscheck": bench.crosschecks}
    (cfg.out / "run.json").write_text(json.dumps(run_info, indent=2) + "\n")
    print(f"bench-accuracy: {len(bench.points)} points in {run_info['wall_seconds']} s")


def vulkan_device(log):
    try:
        out = subprocess.run(["vulkaninfo", "--summary"], capture_output=True, text=True, timeout=60).stdout
        names = re.findall(r"deviceName\s*=\s*(.+)", out)
        return ", ".join(n.strip() for n in names) or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown (vulkaninfo not available)"


if __name__ == "__main__":
    main()
