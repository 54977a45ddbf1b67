"""A careless user's probe of rsf's programs (issue 87's target; docs/reliability.md,
"Round 5's probe"): every value flag of the main programs given nonsense, one at a time,
each in a scratch folder with --max-memory-gb 8 and a time limit (PROBE_LIMIT s, 15 by
default), each outcome classified:

  R  refused, the message naming the flag or the value      U  refused, naming neither
  A  accepted and finished                                   T  accepted, still running at the limit
  P  a panic                                                 O  killed for memory / S another signal
  +N NaN or inf in a text output file (csv, dat, txt, json)

A and T are then judged by hand: a legitimate value (`--max-memory-gb 1e300`, no bound;
`--station-interval 1e-300`) or nonsense that ran (B).

Usage: python3 docs/probe/careless_probe.py target/debug/examples target/debug/pipping_slider OUT.json
(the binaries `cargo test --workspace --all-features --no-run` builds)."""
import json, os, re, shutil, signal, subprocess, sys, tempfile, time

PROGRAMS = ["pipping_slider","slider_3d","seas_bp1","seas_bp3","seas_bp5","seas_bp6","seas_bp7","seas_bp8","stepover","bp5_pair"]
NUMERIC = ["nan", "-1", "1e300", "1e-300"]
LIMIT = float(os.environ.get("PROBE_LIMIT", "15"))
ROOT = os.environ.get("PROBE_SCRATCH", os.path.join(tempfile.gettempdir(), "rsf_probe"))

def values(f):
    name = f["flag"]
    if f["choices"]:
        return ["bogus", ""]
    if name == "--out":
        return ["@file", "/dev/null"]
    if name in ("--resume",):
        return ["/dev/zero", "@fifo", "@dir", "@garbage", "@missing"]
    if name in ("--scene", "--mesh-file", "--gmsh"):
        return ["@fifo", "@garbage", "@dir"]
    if name == "--modeler":
        return ["a b\nc", "x" * 5000]
    if name == "--date":
        return ["2026-13-45", "yesterday"]
    if name == "--allow-change":
        return ["bogus_field"]
    if name == "--window":
        return ["5,1", "nan,1", "1e300,1e301"]
    if "," in (f["value"] or "") or name in ("--steps",):
        return ["1,nan", "-1", "1e300"]
    return NUMERIC

def materialise(v, d):
    if v == "@file":
        p = os.path.join(d, "a_file"); open(p, "w").write("x"); return p
    if v == "@fifo":
        p = os.path.join(d, "fifo"); os.mkfifo(p); return p
    if v == "@dir":
        p = os.path.join(d, "a_dir"); os.makedirs(p); return p
    if v == "@garbage":
        p = os.path.join(d, "garbage.bin"); open(p, "wb").write(os.urandom(4096)); return p
    if v == "@missing":
        return os.path.join(d, "missing.bin")
    return v

def snapshot(d):
    out = {}
    for r, _, fs in os.walk(d):
        for f in fs:
            p = os.path.join(r, f)
            try:
                out[p] = open(p, "rb").read() if os.path.isfile(p) else b"<special>"
            except OSError:
                out[p] = b"<unreadable>"
    return out

NANRE = re.compile(rb"(?<![A-Za-z_])(nan|NaN|inf|-inf)(?![A-Za-z_])")

def run_case(exe, prog, flag, value, idx):
    d = os.path.join(ROOT, f"{idx:04d}")
    shutil.rmtree(d, ignore_errors=True); os.makedirs(d)
    v = materialise(value, d)
    args = [exe, flag, v]
    if flag != "--out":
        args += ["--out", os.path.join(d, "out")]
    if flag != "--max-memory-gb":
        args += ["--max-memory-gb", "8"]
    t0 = time.time()
    p = subprocess.Popen(args, cwd=d, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = p.communicate(timeout=LIMIT); timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL); out, err = p.communicate(); timed_out = True
    dt = time.time() - t0
    err = err.decode("utf8", "replace"); out = out.decode("utf8", "replace")
    rc = p.returncode
    nan_files = []
    for path, b in snapshot(os.path.join(d, "out")).items():
        if path.endswith((".csv", ".dat", ".txt", ".json")) and NANRE.search(b):
            nan_files.append(os.path.relpath(path, d))
    if timed_out: cls = "T"
    elif "panicked" in err or rc == 101: cls = "P"
    elif rc is not None and rc < 0: cls = "O" if "memory allocation" in err else "S"
    elif rc == 0: cls = "A"
    else:
        last = [l for l in err.splitlines() if l.strip()]
        msg = "\n".join(last[-3:])
        named = flag in err or (flag.lstrip("-") in err) or (value not in ("", "bogus") and value[:20] in err)
        cls = "R" if named and "error" in err.lower() else "U"
    if nan_files: cls += "+N"
    shutil.rmtree(d, ignore_errors=True)
    return {"program": prog, "flag": flag, "value": value, "class": cls, "rc": rc, "seconds": round(dt, 2),
            "stderr": err[-600:], "nan_files": nan_files}

def main():
    # Absolute paths: each case runs in a folder of its own.
    bindir, mainjob = (os.path.abspath(p) for p in sys.argv[1:3])
    outpath = sys.argv[3]
    only = sys.argv[4:] or PROGRAMS
    bindir = bindir.rstrip("/") + "/"
    results = []; idx = 0
    os.makedirs(ROOT, exist_ok=True)
    for prog in only:
        exe = mainjob if prog == "pipping_slider" else bindir + prog
        _, fl = _flags_for(exe)
        for f in fl:
            if not f["value"] or f["flag"] in ("--help", "--version"):
                continue
            for v in values(f):
                idx += 1
                r = run_case(exe, prog, f["flag"], v, idx)
                results.append(r)
                print(f'{r["class"]:4} {r["seconds"]:6.2f}s {prog} {f["flag"]} {v[:30]!r}', flush=True)
                json.dump(results, open(outpath, "w"), indent=1)
    from collections import Counter
    print(Counter(r["class"] for r in results))

def _flags_for(exe):
    h = subprocess.run([exe, "--help"], capture_output=True, text=True, timeout=30).stdout
    out = []; cur = None
    for line in h.splitlines():
        m = re.match(r"^\s+(?:-\w, )?--([\w-]+)(?: <([\w.,]+)>)?", line)
        if m and line.strip().startswith("-"):
            cur = {"flag": "--" + m.group(1), "value": m.group(2), "help": "", "choices": []}
            out.append(cur); continue
        if cur is not None:
            cur["help"] += line.strip() + " "
            m2 = re.match(r"^\s+- ([\w-]+):", line)
            if m2: cur["choices"].append(m2.group(1))
            m3 = re.search(r"\[possible values: ([^\]]+)\]", line)
            if m3: cur["choices"] += [c.strip() for c in m3.group(1).split(",")]
    return exe, out

if __name__ == "__main__":
    main()
