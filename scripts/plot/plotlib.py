"""What every viaduct plot shares: units in engineering form from the column names, the title
of the scenario that produced a result, numbers that may be empty (not known), and saving.

Column names carry their unit as a suffix (DESIGN.md): `_mps2`, `_m`, `_N`, ... A plot shows
deflections in mm, forces in kN, moments in kN·m, never "mps2".
"""
import csv
import os
import sys

try:
    import tomllib
except ImportError:  # Python < 3.11: the title is then the directory's name
    tomllib = None

# suffix -> (factor to the shown unit, the unit as printed)
UNITS = {
    "mps2": (1.0, "m/s²"),
    "mps": (1.0, "m/s"),
    "m": (1e3, "mm"),
    "mm": (1.0, "mm"),
    "rad": (1e3, "mrad"),
    "N": (1e-3, "kN"),
    "kN": (1.0, "kN"),
    "Nm": (1e-3, "kN·m"),
    "kNm": (1.0, "kN·m"),
    "ue": (1.0, "µε"),
    "strain": (1e6, "µε"),
    "s": (1.0, "s"),
    "Hz": (1.0, "Hz"),
    "degC": (1.0, "°C"),
}


def split_unit(column):
    """('S1_mid_acc', 1.0, 'm/s²') for 'S1_mid_acc_mps2'; (column, 1.0, '') without a known unit."""
    if "_" in column:
        base, suffix = column.rsplit("_", 1)
        if suffix in UNITS:
            return (base,) + UNITS[suffix]
    return column, 1.0, ""


def unit_label(unit):
    """'m/s²/N' for the FRF unit 'mps2/N': each part in engineering form."""
    return "/".join(UNITS.get(p, (1.0, p))[1] for p in unit.split("/"))


def number(cell):
    """A table cell as a float; None when it is empty (a value viaduct could not determine)."""
    cell = (cell or "").strip()
    return float(cell) if cell else None


def manifest(directory):
    """The manifest.toml of a result directory as a dict ({} when absent or unreadable)."""
    path = os.path.join(directory, "manifest.toml")
    if tomllib is None or not os.path.exists(path):
        return {}
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError):
        return {}


def scenario_title(directory, fallback=None):
    """The scenario's `title` from the manifest, else `fallback` or the directory's name."""
    title = manifest(directory).get("scenario", {}).get("title", "")
    return title or fallback or os.path.basename(os.path.normpath(directory))


def no_offset(ax):
    """Tick labels as the values themselves, never '1e-3 + offset'."""
    ax.ticklabel_format(axis="y", style="plain", useOffset=False)


def save(fig, path, tool, dpi=110):
    fig.savefig(path, dpi=dpi)
    print("wrote", path)


def check_outputs(directory, tool):
    """Exits unless `directory` holds one finished run: its manifest.toml, and every file its
    [[outputs]] list with the SHA-256 written there (viaduct writes the manifest last; a run
    killed before leaves none, and files of another run do not match it)."""
    import hashlib
    if os.path.isfile(directory):  # a script given one of the directory's files
        directory = os.path.dirname(directory) or "."
    if not os.path.isdir(directory):
        sys.exit("%s: %s not found" % (tool, directory))
    # viaduct itself may call a script while it is still writing the directory (its manifest last).
    if os.environ.get("VIADUCT_WRITING") == os.path.abspath(directory):
        return
    path = os.path.join(directory, "manifest.toml")
    if not os.path.exists(path):
        sys.exit("%s: %s has no manifest.toml: the run that wrote it did not finish; its files are not a "
                 "result (run the command again)" % (tool, directory))
    for out in manifest(directory).get("outputs", []):
        name = out.get("file", "")
        target = os.path.join(directory, name)
        if not os.path.exists(target):
            sys.exit("%s: %s, which %s lists, is missing" % (tool, target, path))
        with open(target, "rb") as f:
            if hashlib.sha256(f.read()).hexdigest() != out.get("sha256"):
                sys.exit("%s: %s changed since the run that wrote %s: the directory holds files of two runs"
                         % (tool, target, path))


def need(path, tool, command):
    if not os.path.exists(path):
        sys.exit("%s: %s not found (run viaduct %s first)" % (tool, path, command))
    check_outputs(os.path.dirname(path) or ".", tool)  # the files of one finished run


def rows(path, tool, command):
    """The rows of a CSV that `viaduct COMMAND` wrote (dicts by column name); exits naming the
    command to run when it is missing or when its directory is not one finished run."""
    need(path, tool, command)
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def dir_parser(doc):
    """The argument parser of a script that draws one result directory: `dir`, then the
    script's own options (its docstring as the description)."""
    import argparse
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    return ap


def parse_dir(ap, tool):
    """The parsed arguments of `dir_parser`'s parser, once `dir` holds one finished run."""
    a = ap.parse_args()
    check_outputs(a.dir, tool)
    return a


def run_case(directory):
    """': TRAIN at V km/h' of a `viaduct run` directory ('' when its manifest does not say)."""
    run = manifest(directory).get("run", {})
    if "train" in run and "speed_kmh" in run:
        return ": %s at %.1f km/h" % (run["train"], float(run["speed_kmh"]))
    return ""


def numeric_table(path, tool, hint):
    """(header, data): the column names of a numeric CSV viaduct wrote and its rows as a 2-D
    array; exits '<tool>: <path> not found (<hint>)' when it is missing."""
    import numpy as np
    if not os.path.exists(path):
        sys.exit("%s: %s not found (%s)" % (tool, path, hint))
    with open(path, newline="") as f:
        header = next(csv.reader(f))
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def pyplot():
    """matplotlib.pyplot on the Agg backend: every plot is a file, drawn without a display."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def rows_reader(tool, command):
    """rows() of `tool` for the files of `viaduct COMMAND`: a function of the path."""
    return lambda path: rows(path, tool, command)
