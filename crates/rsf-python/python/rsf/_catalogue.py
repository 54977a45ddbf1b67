"""The event catalogue of a fault network (``catalogue.csv``) as numpy arrays."""

import csv

import numpy as np


def read_catalogue(path):
    """Read a fault network's ``catalogue.csv`` (docs/fault-networks.md, "Output").

    Returns a dict of numpy arrays, one entry per event (``n`` events, ``F`` faults,
    ``D`` coordinates):

    - ``faults``: the faults' names (list of ``F`` str, the file's order);
    - ``onset``, ``end``, ``duration``: times (s), shape ``(n,)``; ``end`` and
      ``duration`` are NaN for an event still under way;
    - ``nucleation_fault``: the name of the fault where each event nucleated, ``(n,)``;
    - ``nucleation_x``: where (m), ``(n, D)``;
    - ``ruptured``: whether each fault ruptured, bool ``(n, F)``;
    - ``peak_slip_rate`` (m/s), ``moment`` (N m; per metre in 2-D) and ``rupture``
      (time of the fault's first crossing of the onset threshold, s; NaN where it did
      not rupture), each ``(n, F)``.

    Raises ``ValueError`` naming the file for a header that is not a catalogue's.
    """
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty, not a catalogue")
    header, body = rows[0], rows[1:]
    fixed = ["event", "onset_s", "end_s", "duration_s", "nucleation_fault"]
    if header[: len(fixed)] != fixed or "ruptured" not in header:
        raise ValueError(f"{path}: not a catalogue.csv header: {header[:6]}")
    r = header.index("ruptured")
    axes = header[len(fixed) : r]
    per_fault = header[r + 1 :]
    if len(per_fault) % 3 != 0 or not axes:
        raise ValueError(f"{path}: the per-fault columns are not triples: {per_fault}")
    prefix = "peak_slip_rate_"
    faults = [c[len(prefix) :] for c in per_fault[0::3]]
    for name, m, t in zip(faults, per_fault[1::3], per_fault[2::3]):
        if m != f"moment_{name}" or t != f"rupture_s_{name}":
            raise ValueError(f"{path}: the columns of fault {name!r} are {m!r}, {t!r}")

    def num(s):
        return float(s) if s != "" else np.nan

    n, nf = len(body), len(faults)
    out = {
        "faults": faults,
        "onset": np.array([num(row[1]) for row in body], dtype=float),
        "end": np.array([num(row[2]) for row in body], dtype=float),
        "duration": np.array([num(row[3]) for row in body], dtype=float),
        "nucleation_fault": np.array([row[4] for row in body], dtype=object),
        "nucleation_x": np.array(
            [[num(v) for v in row[len(fixed) : r]] for row in body], dtype=float
        ).reshape(n, len(axes)),
        "ruptured": np.zeros((n, nf), dtype=bool),
    }
    for key, k in (("peak_slip_rate", 0), ("moment", 1), ("rupture", 2)):
        out[key] = np.array(
            [[num(row[r + 1 + 3 * j + k]) for j in range(nf)] for row in body], dtype=float
        ).reshape(n, nf)
    for i, row in enumerate(body):
        names = [s for s in row[r].split(";") if s]
        for s in names:
            if s not in faults:
                raise ValueError(f"{path}: event {row[0]} ruptured an unknown fault {s!r}")
            out["ruptured"][i, faults.index(s)] = True
    return out
