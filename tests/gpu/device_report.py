#!/usr/bin/env python3
"""Helper of tests/gpu/check_on_device.sh (standard library only).

  device_report.py agreement CPU_WS GPU_WS KIND  how far two workspaces' KIND (photometric or
                                                 geometric) depth maps agree (one JSON line)
  device_report.py scene SCENE_DIR               SCENE_DIR/scene.json from what the script left
                                                 there (layout: SCENE_FILES below)
  device_report.py report WORK_DIR REPORT_FILE   writes the report REPORT_FILE: the header lines
                                                 check_on_device.sh wrote to WORK_DIR/header.txt,
                                                 then tables with a row per scene named in
                                                 WORK_DIR/scenes.txt (layout: kernels/DESIGN_CUDA.md,
                                                 "Checking on a device", step 7)

Depth maps are read as colmap_ext/io/mat_io.cc writes them: the text header "W&H&C&", then
W*H*C little-endian float32, channel-major (planar), each channel row-major; 0 = no depth.
"""
import array
import json
import math
import os
import re
import sys

TIGHT = 1e-4  # the agreement of issue 34: relative depth difference <= 1e-4
LOOSE = 1e-2  # the evaluation's headline tolerance (1 %)


def read_depth_map(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    for _ in range(3):
        end = data.index(b"&", pos)
        fields.append(int(data[pos:end].decode("ascii")))
        pos = end + 1
    width, height, channels = fields
    values = array.array("f")
    values.frombytes(data[pos:])
    if sys.byteorder != "little":
        values.byteswap()
    if len(values) != width * height * channels:
        raise ValueError(f"{path}: header says {width}x{height}x{channels}, data holds {len(values)} floats")
    return width, height, values[: width * height]  # channel 0


def depth_agreement(cpu_ws, gpu_ws, kind):
    """Over the pixels with a depth in either map (a pixel with a depth in one only disagrees):
    the share whose relative difference |gpu - cpu| / cpu is <= TIGHT and <= LOOSE."""
    suffix = f".{kind}.bin"
    cpu_dir = os.path.join(cpu_ws, "stereo", "depth_maps")
    names = sorted(n for n in os.listdir(cpu_dir) if n.endswith(suffix))
    either = tight = loose = only_one = 0
    largest = 0.0
    problems = []
    for name in names:
        gpu_path = os.path.join(gpu_ws, "stereo", "depth_maps", name)
        if not os.path.exists(gpu_path):
            problems.append(f"{name} missing in the GPU run")
            continue
        wc, hc, cpu = read_depth_map(os.path.join(cpu_dir, name))
        wg, hg, gpu = read_depth_map(gpu_path)
        if (wc, hc) != (wg, hg):
            problems.append(f"{name}: {wc}x{hc} (CPU) against {wg}x{hg} (GPU)")
            continue
        for c, g in zip(cpu, gpu):
            c_valid = c > 0 and math.isfinite(c)
            g_valid = g > 0 and math.isfinite(g)
            if not (c_valid or g_valid):
                continue
            either += 1
            if not (c_valid and g_valid):
                only_one += 1
                continue
            rel = abs(g - c) / c
            largest = max(largest, rel)
            tight += rel <= TIGHT
            loose += rel <= LOOSE
    if not names:
        problems.append(f"no {kind} depth maps in {cpu_dir}")

    def share(n):
        return n / either if either else None

    return {"maps": len(names), "pixels": either, "within_1e-4": share(tight), "within_1e-2": share(loose),
            "depth_in_one_only": share(only_one), "largest_rel_diff": largest if either else None,
            "problems": problems}


def parse_run_log(path):
    """Wall time, maps written, backend, cost samples/s over the stages' wall time, device cache."""
    text = open(path, encoding="utf-8", errors="replace").read()
    out = {"wall_s": None, "written": None, "backend": None, "samples_per_s": None,
           "cache_peak_mb": None, "cache_budget_mb": None, "stages": []}
    m = re.search(r"([\d.]+) s wall, ([\d.]+) s CPU", text)
    if m:
        out["wall_s"] = float(m.group(1))
    m = re.search(r"(\d+) reference images: (\d+) written.*backend (.+)$", text, re.M)
    if m:
        out["written"], out["backend"] = int(m.group(2)), m.group(3).strip()
    samples = seconds = 0.0
    for m in re.finditer(r"stage (\S+)\s+(\d+) computed,\s+\d+ resumed,\s+([\d.]+) s, ([\d.]+) Mpix\*iterations/s, "
                         r"(\d+) cost samples per pixel and iteration", text):
        name, sec, mpix_it_s, per_px_it = m.group(1), float(m.group(3)), float(m.group(4)), float(m.group(5))
        stage_samples = mpix_it_s * 1e6 * sec * per_px_it
        out["stages"].append({"name": name, "seconds": sec, "samples_per_s": stage_samples / sec if sec else 0})
        samples += stage_samples
        seconds += sec
    if seconds > 0:
        out["samples_per_s"] = samples / seconds
    m = re.search(r"CUDA device \d+ cache: .* peak (\d+) MB of (\d+) MB", text)
    if m:
        out["cache_peak_mb"], out["cache_budget_mb"] = int(m.group(1)), int(m.group(2))
    return out


# What check_on_device.sh leaves in a scene's folder.
SCENE_FILES = {
    "ws_cpu_1it": "workspace after one photometric iteration on the CPU",
    "ws_gpu_1it": "the same on the GPU",
    "ws_cpu": "workspace after the whole default run on the CPU",
    "ws_gpu": "the same on the GPU",
    "log_cpu.txt": "log of the whole CPU run (log_gpu.txt, log_cpu_1it.txt, log_gpu_1it.txt alike)",
    "eval_cpu/evaluation.json": "colmap-mp evaluate of ws_cpu (eval_gpu/ of ws_gpu)",
    "gpu_memory.txt": "nvidia-smi memory.used (MiB) every 100 ms during the whole GPU run",
    "gpu_memory_before.txt": "one such reading before it",
    "notes.txt": "lines for the report's notes",
}


def f1_at_1_percent(path):
    if not os.path.exists(path):
        return None
    for t in json.load(open(path))["workspaces"][0]["depth"]["pooled"]["tolerances"]:
        if abs(t["tolerance"] - 0.01) < 1e-9:
            return t["f1"]
    return None


def scene_summary(scene_dir):
    def there(name):
        return os.path.join(scene_dir, name)

    s = {"scene": os.path.basename(os.path.normpath(scene_dir)), "notes": []}
    if os.path.exists(there("notes.txt")):
        s["notes"] = [f"{s['scene']}: {l.strip()}" for l in open(there("notes.txt")) if l.strip()]
    for run in ("cpu", "gpu"):
        if os.path.exists(there(f"log_{run}.txt")):
            s[run] = parse_run_log(there(f"log_{run}.txt"))
        s[f"f1_{run}"] = f1_at_1_percent(there(f"eval_{run}/evaluation.json"))
    for key, suffix, kind in (("agreement_1it", "_1it", "photometric"), ("agreement_run", "", "geometric")):
        if os.path.isdir(there(f"ws_cpu{suffix}")) and os.path.isdir(there(f"ws_gpu{suffix}")):
            s[key] = depth_agreement(there(f"ws_cpu{suffix}"), there(f"ws_gpu{suffix}"), kind)
            s["notes"] += [f"{s['scene']}: {p}" for p in s[key]["problems"]]
    if os.path.exists(there("gpu_memory.txt")):
        s["memory_peak_mib"] = peak(there("gpu_memory.txt"))
    if os.path.exists(there("gpu_memory_before.txt")):
        s["memory_before_mib"] = peak(there("gpu_memory_before.txt"))
    with open(there("scene.json"), "w") as f:
        json.dump(s, f, indent=1)


def peak(path):
    values = []
    for line in open(path, encoding="utf-8", errors="replace"):
        try:
            values.append(float(line.strip().split()[0]))
        except (ValueError, IndexError):
            pass
    return max(values) if values else None


def fmt(value, spec, missing="-"):
    return missing if value is None or (isinstance(value, float) and math.isnan(value)) else format(value, spec)


def pct(value):
    return fmt(None if value is None else 100 * value, ".2f")


def write_report(work_dir, report_path):
    scenes = []
    for name in open(os.path.join(work_dir, "scenes.txt")).read().split():
        path = os.path.join(work_dir, name, "scene.json")
        scenes.append(json.load(open(path)) if os.path.exists(path) else {"scene": name, "notes": [f"{name}: not run"]})
    lines = [open(os.path.join(work_dir, "header.txt")).read().rstrip(), ""]
    lines += ["## Agreement of the depth maps, GPU against CPU",
              "",
              "Pixels with a depth in either map; a pixel with a depth in one map only disagrees. "
              "One iteration: `--MPMVS.max_window_scale 0 --MPMVS.iterations_per_scale 1 "
              "--PatchMatchStereo.geom_consistency 0` (photometric maps, before PatchMatch can amplify a "
              "rounding difference; issue 34 asks >= 99.9 % within 1e-4). Whole run: the default pipeline "
              "(geometric maps).",
              "",
              "Shares in %.",
              "",
              "| scene | maps | 1 iteration: within 1e-4 | within 1 % | depth in one only | largest rel. diff "
              "| whole run: within 1e-4 | within 1 % | depth in one only |",
              "|---|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        a, b = s.get("agreement_1it") or {}, s.get("agreement_run") or {}
        lines.append(f"| {s['scene']} | {b.get('maps', '-')} | {pct(a.get('within_1e-4'))} | "
                     f"{pct(a.get('within_1e-2'))} | {pct(a.get('depth_in_one_only'))} | "
                     f"{fmt(a.get('largest_rel_diff'), '.2e')} | {pct(b.get('within_1e-4'))} | "
                     f"{pct(b.get('within_1e-2'))} | {pct(b.get('depth_in_one_only'))} |")
    lines += ["",
              "## Quality and speed of the whole default run",
              "",
              "F1: depth F1@1 % in %, pooled (`colmap-mp evaluate`, docs/evaluation.md §2; issue 34 asks the GPU "
              "within 0.2 point of the CPU). Time per map: the run's wall time over the maps it wrote. "
              "Samples/s: cost samples (one window point matched in one source view) over the stages' wall "
              "time, host work between images included, so a lower bound of the device's rate. Device "
              "memory: peak of `nvidia-smi --query-gpu=memory.used` sampled every 100 ms during the GPU "
              "run, minus the reading before it; cache: the log's `CUDA device N cache` peak.",
              "",
              "| scene | F1 CPU | F1 GPU | GPU - CPU | s/map CPU | s/map GPU | speed-up | samples/s CPU "
              "| samples/s GPU | device memory MiB (peak - before) | device cache peak MB |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        cpu, gpu = s.get("cpu") or {}, s.get("gpu") or {}
        f_cpu, f_gpu = s.get("f1_cpu"), s.get("f1_gpu")
        diff = None if f_cpu is None or f_gpu is None else f_gpu - f_cpu
        per_map = {}
        for k, r in (("cpu", cpu), ("gpu", gpu)):
            per_map[k] = r["wall_s"] / r["written"] if r.get("wall_s") is not None and r.get("written") else None
        speedup = (per_map["cpu"] / per_map["gpu"] if per_map["cpu"] and per_map["gpu"] else None)
        mem_peak, mem_before = s.get("memory_peak_mib"), s.get("memory_before_mib")
        mem = (f"{mem_peak - mem_before:.0f} ({mem_peak:.0f} - {mem_before:.0f})"
               if mem_peak is not None and mem_before is not None else "-")
        lines.append(f"| {s['scene']} | {pct(f_cpu)} | {pct(f_gpu)} | {fmt(None if diff is None else 100 * diff, '+.2f')} | "
                     f"{fmt(per_map['cpu'], '.2f')} | {fmt(per_map['gpu'], '.2f')} | {fmt(speedup, '.1f')} | "
                     f"{fmt(cpu.get('samples_per_s'), '.3g')} | {fmt(gpu.get('samples_per_s'), '.3g')} | {mem} | "
                     f"{fmt(gpu.get('cache_peak_mb'), 'd')} |")
    lines += ["", "## GPU samples/s stage by stage", ""]
    for s in scenes:
        stages = [st for st in (s.get("gpu") or {}).get("stages") or [] if st["samples_per_s"] > 0]
        if stages:
            lines.append(f"- {s['scene']}: " + ", ".join(f"{st['name']} {st['samples_per_s']:.3g}" for st in stages))
    notes = [n for s in scenes for n in s.get("notes", [])]
    if notes:
        lines += ["", "## Notes", ""] + [f"- {n}" for n in notes]
    with open(report_path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv):
    if len(argv) == 5 and argv[1] == "agreement":
        print(json.dumps(depth_agreement(argv[2], argv[3], argv[4])))
    elif len(argv) == 3 and argv[1] == "scene":
        scene_summary(argv[2])
    elif len(argv) == 4 and argv[1] == "report":
        write_report(argv[2], argv[3])
    else:
        sys.stderr.write(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
