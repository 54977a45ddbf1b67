"""pandas and xarray views of a simulation's records (imported on demand)."""


def series_frame(series):
    """The per-step series as a pandas DataFrame indexed by time ``t`` (s)."""
    import pandas as pd

    frame = pd.DataFrame({k: v for k, v in series.items() if k != "t"})
    frame.index = pd.Index(series["t"], name="t")
    return frame


def events_frame(events):
    """The event catalogue as a pandas DataFrame, one row per event."""
    import pandas as pd

    return pd.DataFrame(events)


def fault_dataset(fault):
    """The fault records as an xarray Dataset on dimensions (t, node[, component]), each
    node's fault name a coordinate ``fault``."""
    import xarray as xr

    x = fault["x"]
    coords = {"t": fault["t"], "node": range(x.shape[0])}
    for i, name in enumerate("xyz"[: x.shape[1]]):
        coords[name] = ("node", x[:, i])
    if "fault" in fault:
        # The fault of every node by name (a network's: rsf.Model(faults=...)).
        names = list(fault["fault_names"])
        coords["fault"] = ("node", [names[i] for i in fault["fault"]])
    data = {
        "slip_rate": (("t", "node"), fault["slip_rate"], {"units": "m/s"}),
        "alpha": (("t", "node"), fault["alpha"], {"units": "1", "long_name": "ln theta (theta in s)"}),
        "slip": (("t", "node", "component"), fault["slip"], {"units": "m"}),
        "shear_traction": (("t", "node"), fault["shear_traction"], {"units": "Pa"}),
    }
    ds = xr.Dataset(data, coords=coords)
    ds["t"].attrs["units"] = "s"
    return ds
