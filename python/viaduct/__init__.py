"""viaduct in Python: scenarios, runs, sweeps, records and signals on numpy arrays.

The computation is the C++ core's (the same functions as the ``viaduct`` command line); this
package is a thin layer over it. Errors are ``viaduct.InputError`` (a ``ValueError``) and
``viaduct.SolverError`` (a ``RuntimeError``) with the command line's text: file, line and key.
Tables are pandas DataFrames when pandas is installed, dicts of numpy arrays otherwise.

    import viaduct
    sc = viaduct.load_scenario("scenarios/hslm-simply-supported.toml")
    sc.set("sweep.speed_step_kmh", 10.0)
    env = viaduct.sweep(sc, threads=0)        # envelope.csv's columns
"""
import math

from . import _viaduct
from ._viaduct import InputError, SolverError

__all__ = ["Scenario", "load_scenario", "scenario_from_dict", "run", "sweep", "assess", "passages", "sampled_sweep", "Record", "read_record", "filter",
           "spectrum", "welch", "compare", "peaks", "identify_speed", "frf", "record_frf", "read_frf", "modal_fit",
           "decay", "oma", "track_modes", "fit", "rainflow", "miner_damage", "fatigue_mix", "InputError", "SolverError", "version"]


def version():
    """viaduct's version ("x.y.z", as in manifest.toml)."""
    return _viaduct.version()


def _toml(value, key):
    """A Python value as the TOML literal of a --set override."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise InputError(f"key '{key}': {value} is not a finite number")
        return repr(value)
    if isinstance(value, str):
        escaped = value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\t", "\\t")
        return '"' + escaped + '"'
    if hasattr(value, "tolist"):  # numpy scalars and arrays
        return _toml(value.tolist(), key)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v, key) for v in value) + "]"
    raise InputError(f"key '{key}': cannot set a value of type {type(value).__name__}")


def _flatten(d, prefix, out):
    """Nested dicts (tables) and lists of dicts (arrays of tables) to dotted keys."""
    for k, v in d.items():
        key = f"{prefix}.{k}" if prefix else str(k)
        if isinstance(v, dict):
            _flatten(v, key, out)
        elif isinstance(v, (list, tuple)) and v and all(isinstance(x, dict) for x in v):
            for i, item in enumerate(v):
                _flatten(item, f"{key}[{i}]", out)
        else:
            out.append((key, v))
    return out


class Scenario:
    """A scenario: a file (or a dict) with its overrides, checked as ``viaduct check`` checks it."""

    def __init__(self, path, overrides=()):
        self._path = path
        self._overrides = list(overrides)
        self._flat = _viaduct.load_flat(path, self._overrides)

    @property
    def path(self):
        """The scenario file ("" for a scenario built from a dict)."""
        return self._path

    @property
    def overrides(self):
        """The ``key=value`` overrides set so far, as ``viaduct --set`` takes them."""
        return list(self._overrides)

    def set(self, key, value):
        """Sets a key (checked as ``--set key=value``: type, constraint, cross-key rules); returns self."""
        # The key's earlier override replaced: a loop of sets does not pile them up.
        overrides = [o for o in self._overrides if o.split("=", 1)[0] != key] + [f"{key}={_toml(value, key)}"]
        self._flat = _viaduct.load_flat(self._path, overrides)  # raises and leaves the scenario as it was
        self._overrides = overrides
        return self

    def get(self, key):
        """The resolved value of a key (defaults included)."""
        return self._flat.get(key)

    def keys(self):
        """Every resolved key."""
        return self._flat.keys()

    def where(self, key):
        """(file, line) where a key's value comes from ("--set" for overrides, "default")."""
        return self._flat.where(key)

    def describe(self):
        """The resolved scenario as ``viaduct check`` prints it: key = value  # unit, origin."""
        return self._flat.describe()

    def to_toml(self):
        """The resolved scenario as TOML (as in manifest.toml)."""
        return self._flat.resolved_toml()

    def __repr__(self):
        return f"viaduct.Scenario({self._path!r}, {len(self._overrides)} overrides)"


def load_scenario(path, set=None):
    """Reads a scenario file; ``set`` is a dict of key -> value applied as ``--set``."""
    overrides = [f"{k}={_toml(v, k)}" for k, v in (set or {}).items()]
    return Scenario(str(path), overrides)


def scenario_from_dict(d):
    """A scenario from a dict shaped as the TOML file (tables as dicts, arrays of tables as lists
    of dicts, or dotted keys). Checked as ``--set`` values are; relative paths are from the
    working directory."""
    return Scenario("", [f"{k}={_toml(v, k)}" for k, v in _flatten(d, "", [])])


def _table(columns):
    """A DataFrame when pandas is there, else the dict of columns."""
    try:
        import pandas
    except ImportError:
        return columns
    return pandas.DataFrame(columns)


def _with_attrs(table, info):
    """`table` with `info` in its attrs (a DataFrame), or under "attrs" (the dict of columns)."""
    try:
        table.attrs.update(info)
    except AttributeError:
        table["attrs"] = info
    return table


def _progress_printer(what):
    import sys

    def show(done, total):
        sys.stderr.write(f"\r{what}: {done}/{total} cases")
        if done == total:
            sys.stderr.write("\n")
        sys.stderr.flush()
    return show


def assess(scenario, threads=1, progress=False, out=None):
    """The EN 1991-2 dynamic check of the scenario's bridge, as ``viaduct assess`` (docs/assess.md):
    HSLM-A1…A10 and the scenario's trains at speeds to 1.2 x assess.line_speed_kmh, damping of
    Table 6.6, the mass bounds, the frequency cut-off, every check. Returns checks.csv's columns
    (check, quantity, value, limit, utilisation, result, variant, train, speed_kmh, clause);
    ``attrs``: "envelope", "load_effects", "phi_dyn" (tables), f1_hz, f3_hz, cutoff_hz,
    damping_ratio, n_cases, n_failed, notes and "report" (report.md's text). ``out``: a directory
    for the CLI's tables and report.md (no figures). Ctrl-C stops it and raises KeyboardInterrupt."""
    cb = _progress_printer("assess") if progress is True else (progress or None)
    checks, tables, info = _viaduct.assess(scenario._flat, threads, cb, None if out is None else str(out))
    info.update({k: _table(v) for k, v in tables.items()})
    table = _table(checks)
    return _with_attrs(table, info)


def _read_table(path):
    """A CSV the library wrote, as _table gives tables (a DataFrame with pandas, else columns)."""
    try:
        import pandas
        return pandas.read_csv(path)
    except ImportError:
        import csv
        import numpy as np
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        columns = {}
        for j, name in enumerate(rows[0]):
            cells = [r[j] for r in rows[1:]]
            try:
                columns[name] = np.array([float(c) if c else np.nan for c in cells])
            except ValueError:
                columns[name] = cells
        return columns


def sampled_sweep(scenario, out, threads=1, resume=False, progress=False):
    """A sampled study (sweep.mode = "sample", docs/sampled.md), as ``viaduct sweep`` runs it: the
    samples' peaks streamed into ``out`` batch by batch, then the statistics. Returns
    peak_percentiles.csv (per train and station: the peak over the speeds, its mean, sd,
    percentiles and probability of exceeding the limit with its standard error); ``attrs``:
    "percentiles" (per speed), "samples", "sample_peaks", "failures", with sweep.sensitivity
    "sensitivity" and "peak_sensitivity" (tables read from ``out``), n_samples_total,
    n_samples_run, n_cases_run, n_failed_run, warnings. ``resume=True`` carries on an interrupted
    run in ``out``. Ctrl-C stops the running samples and raises KeyboardInterrupt; ``out`` then holds
    the whole batches before it, which ``resume=True`` carries on (as the CLI's --resume)."""
    import os
    cb = _progress_printer("sampled sweep") if progress is True else (progress or None)
    info = _viaduct.sampled_sweep(scenario._flat, str(out), threads, resume, cb)
    if info["n_failed_run"]:  # as the CLI's exit 1: the statistics use the samples that completed
        import warnings
        warnings.warn(f"sampled_sweep: {info['n_failed_run']} of {info['n_cases_run']} cases failed ({out}/failures.csv); "
                      "the statistics use the samples that completed", stacklevel=2)
    names = ["percentiles", "samples", "sample_peaks", "failures"]
    if info["sensitivity"]:
        names += ["sensitivity", "peak_sensitivity"]
    for name in names:
        info[name] = _read_table(os.path.join(str(out), name + ".csv"))
    table = _read_table(os.path.join(str(out), "peak_percentiles.csv"))
    return _with_attrs(table, info)


def passages(scenario, records, map, train=None, v_min_kmh=None, v_max_kmh=None, speed_band=3.0, noise_band=4.0,
             zero="keep", time_column="", fs_hz=None, header_line=0, skip_lines=0, threads=1, progress=False, out=None):
    """Recorded passages over the model's speed envelope, as ``viaduct passages`` (docs/records.md):
    each record's speed identified from the train's signature (or a table's speed_kmh), each mapped
    channel's peak under the scenario's [filter] against the model's at that speed and over the
    speed's uncertainty, and the model's envelope at the scenario's sweep speeds.

    records  folders of records, or tables (CSV: file[,train][,speed_kmh]; files relative to it)
    map      {channel: station}, in order: the first channel identifies the speed
    train    the train of records without one: a scenario train's name or a train file
    zero     deflection and strain channels' zero: "keep", "pre-entry" or "START:END"
    time_column, fs_hz, header_line, skip_lines  how the records are read, as the CLI's
             --time-column, --rate-hz, --header-line and --skip-lines (read_record's)
    out      a directory for the CLI's tables (passages.csv, passages_summary.csv,
             model_envelope.csv, failures.csv); None: none written

    Returns passages.csv's columns (one row per passage and channel: measured, predicted,
    predicted_low/high, ratio, noise_rms, within, residual, speed and its uncertainty, ...);
    ``attrs``: "passages_summary", "model_envelope", "failures" (tables), "warnings" (what the CLI
    prints as warnings, what reading the records repaired first), n_passages, n_failed; each warning
    and each failed passage is also a UserWarning. A record that cannot be read is a row of
    "failures" and the others complete. Ctrl-C stops the
    simulations and raises KeyboardInterrupt."""
    if isinstance(records, (str, bytes)) or hasattr(records, "__fspath__"):
        records = [records]
    cb = _progress_printer("passages") if progress is True else (progress or None)
    rows, tables, info = _viaduct.passages(scenario._flat, [str(r) for r in records], [f"{k}={v}" for k, v in map.items()],
                                           train, v_min_kmh, v_max_kmh, speed_band, noise_band, zero, time_column, fs_hz,
                                           header_line, skip_lines, threads, cb, None if out is None else str(out))
    info.update({k: _table(v) for k, v in tables.items()})
    # What the CLI prints on stderr (and exits 1 for) is a UserWarning here, not only in attrs.
    import warnings
    for w in info["warnings"]:
        warnings.warn("passages: " + w, stacklevel=2)
    failures = tables["failures"]
    for name, message in zip(failures["passage"], failures["message"]):
        warnings.warn(f"passages: failed: {name}: {message}", stacklevel=2)
    table = _table(rows)
    return _with_attrs(table, info)


def run(scenario, speed_kmh=None, train=None, progress=None):
    """One train at one speed: history.csv's columns (t_s, per station disp, acc, filtered acc,
    then the load effects) as a DataFrame or dict of numpy arrays; ``attrs``: train, speed_kmh,
    method, n_steps, n_modes and, with vehicle models, "vehicles" (vehicles.csv's columns: each
    axle's contact force, each car body's acceleration) — without pandas under the key "attrs".
    ``train``: a train name (default the first); ``speed_kmh`` defaults to run.speed_kmh. Ctrl-C stops the time stepping
    and raises KeyboardInterrupt."""
    names, columns, info = _viaduct.run(scenario._flat, speed_kmh, train, progress)
    if "vehicles" in info:
        info["vehicles"] = _table(info["vehicles"])
    table = _table(dict(zip(names, columns)))
    return _with_attrs(table, info)


def sweep(scenario, threads=1, load_effects=False, progress=False):
    """Speeds x trains x variants: envelope.csv's columns (variant, KEY_factor per varied key,
    train, speed_kmh, station, max_abs_acc_mps2, max_abs_disp_m). ``threads`` as the CLI's (0: all
    cores). ``progress``: True prints to stderr, or a callable(done, total). Ctrl-C stops the
    running cases' time stepping, skips the others and raises KeyboardInterrupt. The sweep's other
    files are in the table's ``attrs`` (DataFrames) or, without pandas, under these keys of the
    dict: "failures" (failures.csv), "governing" (governing.csv), with ``load_effects``
    "load_effects" (load_effects.csv), with vehicle models "vehicles" (vehicles.csv). Failed cases
    (the CLI lists them and exits 1) are a UserWarning naming how many and the first: the envelope
    lacks them."""
    import warnings
    cb = _progress_printer("sweep") if progress is True else (progress or None)
    tables, failures, governing = _viaduct.sweep(scenario._flat, threads, load_effects, cb)
    if failures:
        v, t, kmh, err = failures[0]
        warnings.warn(f"sweep: {len(failures)} cases failed and are not in the envelope (attrs['failures']); "
                      f"the first: {t} at {kmh:.6g} km/h ({v}): {err}", stacklevel=2)
    fail = {"variant": [f[0] for f in failures], "train": [f[1] for f in failures],
            "speed_kmh": [f[2] for f in failures], "error": [f[3] for f in failures]}
    gov_names = ["station", "max_abs_acc_mps2", "acc_variant", "acc_train", "acc_speed_kmh", "max_abs_disp_m",
                 "disp_variant", "disp_train", "disp_speed_kmh"]
    gov = {n: [g[i] for g in governing] for i, n in enumerate(gov_names)}
    extra = {"failures": fail, "governing": gov}
    extra.update({k: v for k, v in tables.items() if k != "envelope"})
    table = _table(tables["envelope"])
    if isinstance(table, dict):
        return dict(table, **extra)
    for k, v in extra.items():
        table.attrs[k] = _table(v)
    return table


class Record:
    """A record read as the CLI reads it: ``data`` (samples x channels, float64, the reader's own
    memory), ``channels`` (names with their unit suffix), ``units``, ``fs_hz``, ``t0_s``."""

    def __init__(self, data, channels, units, fs_hz, t0_s):
        self.data, self.channels, self.units, self.fs_hz, self.t0_s = data, channels, units, fs_hz, t0_s

    @property
    def t(self):
        """Time of each sample [s]."""
        import numpy
        return self.t0_s + numpy.arange(self.data.shape[0]) / self.fs_hz

    def __getitem__(self, channel):
        """A channel's samples (a view, no copy)."""
        if channel not in self.channels:
            raise InputError(f"no channel '{channel}' in the record; it has: {', '.join(self.channels)}")
        return self.data[:, self.channels.index(channel)]

    def to_frame(self):
        """t_s and every channel as a DataFrame (pandas) or dict of arrays."""
        cols = {"t_s": self.t}
        cols.update({c: self.data[:, j] for j, c in enumerate(self.channels)})
        return _table(cols)

    def __repr__(self):
        return f"viaduct.Record({self.data.shape[0]} samples x {len(self.channels)} channels at {self.fs_hz} Hz)"


def read_record(path, time_column="", fs_hz=None, header_line=0, skip_lines=0):
    """Reads a record in any format the CLI reads (CSV of any layout, MATLAB .mat, UFF 58), with
    the CLI's --time-column, --rate-hz, --header-line and --skip-lines. A channel's samples that
    are missing (a long NaN run, a gap, a clipped stretch: docs/records.md) are NaN in that
    channel only."""
    return Record(*_viaduct.read_record(str(path), time_column, fs_hz, header_line, skip_lines))


def filter(x, fs_hz, low_hz=1.0, high_hz=30.0, order=3, ripple_db=0.5, band="bandpass"):
    """Zero-phase Chebyshev I filter, as scipy.signal.sosfiltfilt(cheby1(order, ripple_db, edges,
    band, fs=fs_hz, output="sos"), x) and ``viaduct filter``. A contiguous float64 array is read
    in place; the result is handed over without a copy."""
    return _viaduct.filter(x, fs_hz, low_hz, high_hz, order, ripple_db, band)


def spectrum(x, fs_hz, window="hann"):
    """One-sided amplitude spectrum 2|X|/sum(w) (frequency_hz, amplitude in x's unit), as ``viaduct spectrum``
    (Hann window by default; "rectangular" reads a sine's amplitude on any bin)."""
    return _viaduct.spectrum(x, fs_hz, window)


def welch(x, fs_hz, nperseg=256, noverlap=None, window="hann", detrend="constant"):
    """Welch power spectral density (frequency_hz, density in unit^2/Hz), as scipy.signal.welch."""
    return _viaduct.welch(x, fs_hz, nperseg, -1 if noverlap is None else noverlap, window, detrend)


def rainflow(x, method="three-point", hysteresis=0.0):
    """Rainflow cycles of a history (range, mean, count), as ``viaduct fatigue`` counts them:
    ASTM E1049 three-point (half cycles for the residue) or "four-point"; reversals smaller than
    ``hysteresis`` are not turning points. docs/fatigue.md."""
    return _viaduct.rainflow(x, method, hysteresis)


def miner_damage(ranges, counts, detail=None, delta_c_mpa=None, m1=3.0, m2=5.0, to_pa=1.0, gamma_ff=1.0, gamma_mf=1.0):
    """Palmgren-Miner damage of cycles (ranges in the history's unit times ``to_pa``) against
    EN 1993-1-9's curve of a ``detail`` category [MPa], or a curve of your own (``delta_c_mpa``
    at 2e6 cycles, slopes ``m1`` to 5e6 and ``m2`` to 1e8), each range times gamma_ff*gamma_mf."""
    return _viaduct.miner_damage(ranges, counts, detail or 0.0, delta_c_mpa or 0.0, m1, m2, to_pa, gamma_ff, gamma_mf)


def fatigue_mix(scenario, mix, channel, detail=None, delta_c_mpa=None, m1=3.0, m2=5.0, section_modulus_m3=None,
                youngs_modulus_pa=210e9, gamma_ff=1.0, gamma_mf=1.0, method="three-point", hysteresis_mpa=0.0,
                range_bin_mpa=1.0, mean_bin_mpa=5.0, threads=1, progress=False):
    """Fatigue damage of a traffic mix over the scenario's model (`viaduct fatigue SCENARIO --mix`):
    each train of `mix` (a mix file, e.g. data/trains/fatigue/mix-standard.toml) runs at its speed,
    the `channel` load effect ("<station>_moment" over `section_modulus_m3`, or "<station>_strain"
    times `youngs_modulus_pa`) is counted against `detail` (an EN 1993-1-9 category) or a curve of
    your own (`delta_c_mpa`, `m1`, `m2`). Returns damage.csv's table (a row per train, the last
    "total"); ``attrs``: "cycles" (cycles.csv's table), title, curve, damage_per_year, years_to_d1,
    n_failed. A train whose run failed is a UserWarning and is left out of the total. ``progress``:
    True prints to stderr, or a callable(done, total) of trains; Ctrl-C raises KeyboardInterrupt."""
    import warnings
    cb = _progress_printer("fatigue_mix") if progress is True else (progress or None)
    damage, cycles, info = _viaduct.fatigue_mix(scenario._flat, str(mix), channel, detail, delta_c_mpa, m1, m2,
                                                section_modulus_m3, youngs_modulus_pa, gamma_ff, gamma_mf, method,
                                                hysteresis_mpa, range_bin_mpa, mean_bin_mpa, threads, cb)
    for name, message in zip(damage["train"], damage["message"]):
        if message and name != "total":
            warnings.warn(f"fatigue_mix: {name} failed: {message}", stacklevel=2)
    info["cycles"] = _table(cycles)
    return _with_attrs(_table(damage), info)


def compare(record, fs_record, model, fs_model, t0_record=0.0, low_hz=1.0, high_hz=30.0, order=3, ripple_db=0.5,
            band="bandpass", filter=True, max_shift_s=60.0, spectrum_max_hz=0.0):
    """A record channel against a model quantity in the same unit, as ``viaduct compare``: both
    filtered alike (at their own rates), the model aligned onto the record (shift_s: record time
    of the model's t = 0), and the metrics peak_record, peak_model, peak_ratio, rms_ratio,
    correlation, f_peak_record_hz, f_peak_model_hz, spectral_correlation, unit_warning (the
    text ``viaduct compare`` warns with when record and model are a unit's factor apart with the
    same shape, e.g. a record in g read as m/s²; "" otherwise), with the overlays t, record,
    model and the spectra frequency_hz, record_amplitude, model_amplitude (a dict)."""
    return _viaduct.compare(record, fs_record, model, fs_model, t0_record, low_hz, high_hz, order, ripple_db, band,
                            filter, max_shift_s, spectrum_max_hz)


def frf(force, responses, fs_hz, units, names=(), force_unit="N", method="welch", estimator="h1", nperseg=4096,
        window="hann", f_min_hz=None, f_max_hz=None, steps=(), settle_cycles=30.0, t0_s=0.0):
    """The FRF of a forced-vibration test, as ``viaduct frf RECORD``: ``force`` (N or kN) and
    ``responses`` (samples x channels; ``units`` per channel: m, mps or mps2; ``names`` the
    stations) at ``fs_hz``. ``method``: "welch" (H1 or H2, ``nperseg``, ``window``), "stepped"
    (``steps``: (t_start_s, t_end_s, frequency_hz) dwells, detected from the force when empty) or
    "swept" (``f_min_hz``/``f_max_hz`` required). A dict: frequency_hz, h (complex, frequencies x
    responses), coherence (Welch) or None, responses, quantities, units, force_unit, n_segments,
    steps (the schedule used)."""
    return _viaduct.frf(force, responses, fs_hz, list(units), list(names), force_unit, method, estimator, nperseg, window,
                        f_min_hz, f_max_hz, [tuple(s) for s in steps], settle_cycles, t0_s)


def record_frf(record, force, responses=None, **options):
    """``frf`` on a Record's channels, named as ``viaduct frf RECORD --force CHANNEL`` names them:
    ``force`` a channel in N or kN, ``responses`` channels in m, mps or mps2 (default: all of
    them); the stations are their names without the quantity tag and unit (S1_mid_acc_mps2 ->
    S1_mid)."""
    if responses is None:
        responses = [c for c, u in zip(record.channels, record.units) if u in ("m", "mps", "mps2")]
    idx = [record.channels.index(c) for c in responses]
    units = [record.units[j] for j in idx]
    names = [record.channels[j][: -len(record.units[j]) - 1] for j in idx]
    f = record.channels.index(force)
    return frf(record.data[:, f], record.data[:, idx], record.fs_hz, units, names, force_unit=record.units[f],
               t0_s=record.t0_s, **options)


def read_frf(path):
    """A frf.csv (viaduct frf) as the dict ``frf`` returns."""
    return _viaduct.read_frf(str(path))


def modal_fit(frf, f_min_hz=0.0, f_max_hz=1e9, max_order=40, cluster_tol=0.005, min_prominence=0.05, refine=True):
    """Modal parameters from an FRF (the dict of ``frf`` or ``read_frf``), as ``viaduct modal-fit``:
    peak picking, circle fits and LSCF with its stabilization diagram. A dict: "modes" (modes.csv's
    columns: method, mode, frequency_hz, damping_ratio, response, note), "stabilization" (order,
    frequency_hz, damping_ratio, status), "lscf_shapes" (per LSCF mode, complex, across the
    responses) and "warnings"."""
    r = _viaduct.modal_fit(frf, f_min_hz, f_max_hz, max_order, cluster_tol, min_prominence, refine)
    r["modes"] = _table(r["modes"])
    r["stabilization"] = _table(r["stabilization"])
    return r


def decay(x, fs_hz, frequency_hz, t0_s=0.0, band_ratio=0.15, order=2, start_s=None, end_s=None):
    """Frequency and damping of one mode from a free decay, as ``viaduct decay``: x band-passed
    around ``frequency_hz`` (f(1 -/+ band_ratio), Chebyshev I of ``order``), the decay from
    ``start_s`` (detected by default) to ``end_s`` (the noise floor). A dict: start_s, end_s,
    n_cycles, frequency_hz, zeta_log_decrement, zeta_envelope_fit, envelope_residual,
    zeta_hilbert, frequency_hilbert_hz, amplitude_start/end, the amplitude laws law_zeta0,
    law_zeta_slope, law_f0_hz, law_f_slope_hz, and "by_amplitude" (t_s, amplitude,
    frequency_hz, damping_ratio per window)."""
    r = _viaduct.decay(x, fs_hz, frequency_hz, t0_s, band_ratio, order, start_s, end_s)
    r["by_amplitude"] = _table(r["by_amplitude"])
    return r


def oma(y, fs_hz, t0_s=0.0, names=None, f_min_hz=0.0, f_max_hz=None, references=None, min_order=2, max_order=60,
        order_step=2, block_rows=0, free_decay=False, decimate=1, start_s=None, end_s=None, window_s=0.0,
        min_periods=200.0, jackknife_blocks=10, **stabilization):
    """Output-only modal identification, as ``viaduct oma``: ``y`` (samples x channels, at
    ``fs_hz``, first sample at ``t0_s``) cut into windows of ``window_s`` (0: one), each identified
    by covariance-driven SSI with ``references`` (channel indices; all by default) over model
    orders ``min_order``..``max_order``, stable poles clustered into modes with jackknife standard
    deviations over ``jackknife_blocks`` pieces, and by FDD/EFDD. ``free_decay``: the free
    vibration after a passage (its start found unless ``start_s``). More keywords set the
    stabilization (tol_frequency, tol_damping, tol_mac, max_damping, min_mpc, max_mpd_deg,
    cluster_distance, min_cluster_fraction) and FDD (nperseg, min_prominence_db, efdd_mac).
    A list of windows, each a dict: t_start_s, t_end_s, error ("" when it went well), warning
    ("" or why the window is not ambient: a burst such as a passage, which warns too),
    block_rows, "modes" (modes.csv's columns), "shapes" (complex, channels x modes), "poles"
    (stabilization.csv's), "fdd" (frequency_hz, singular_values, peak_hz, efdd_frequency_hz,
    efdd_damping_ratio). A window that fails warns (UserWarning) besides its "error"."""
    plan = _viaduct.OmaPlan()
    ssi = plan.ssi
    ssi.f_min_hz = f_min_hz
    if f_max_hz is not None:
        ssi.f_max_hz = f_max_hz
    ssi.references = list(references or [])
    ssi.min_order, ssi.max_order, ssi.order_step, ssi.block_rows = min_order, max_order, order_step, block_rows
    ssi.free_decay = free_decay
    ssi.jackknife_blocks = jackknife_blocks
    fdd = plan.fdd
    for k, v in stabilization.items():
        target = fdd if k in ("nperseg", "min_prominence_db", "efdd_mac") else ssi
        if not hasattr(target, k):
            raise TypeError("oma() got an unexpected keyword argument '%s'" % k)
        setattr(target, k, v)
    plan.ssi, plan.fdd = ssi, fdd
    plan.decimate, plan.window_s, plan.min_periods = decimate, window_s, min_periods
    if start_s is not None:
        plan.start_s = start_s
    if end_s is not None:
        plan.end_s = end_s
    windows = _viaduct.oma(y, fs_hz, t0_s, list(names or []), plan)
    import warnings
    for w in windows:
        w["modes"] = _table(w["modes"])
        w["poles"] = _table(w["poles"])
        # A failed window, or one that is not ambient (a passage): said where the user sees it, as
        # the CLI says each on stderr.
        for said in (w["error"], w["warning"]):
            if said:
                warnings.warn("oma: window %g to %g s: %s" % (w["t_start_s"], w["t_end_s"], said), stacklevel=2)
    return windows


def track_modes(windows, tol_frequency=0.05, min_mac=0.8):
    """Modes of successive windows (oma()'s results, of one record or many) matched into tracks by
    frequency and MAC, as ``viaduct oma`` does over its windows: per window, the track of each mode."""
    pairs = [(list(w["modes"]["frequency_hz"]), w["shapes"] if len(w["modes"]["frequency_hz"]) else None) for w in windows]
    return _viaduct.track_modes(pairs, tol_frequency, min_mac)


def peaks(y, min_height=None, min_prominence=0.0, min_distance=1, max_peaks=0, interpolation="gaussian"):
    """Peaks of a sampled curve, after scipy.signal.find_peaks (height, prominence and distance
    filters; flat tops at their middle), positions refined between samples ("gaussian",
    "parabolic" or "none"). A dict of index, position (samples), value and prominence."""
    return _viaduct.peaks(y, -math.inf if min_height is None else min_height, min_prominence, min_distance, max_peaks,
                          interpolation)


def identify_speed(x, fs_hz, distance_m, method="spectrum", v_min_kmh=40.0, v_max_kmh=400.0, harmonics=4,
                   min_interval_s=0.1):
    """A train's speed from a record, as ``viaduct speed --distance-m``: "spectrum" (the comb of
    ``harmonics`` lines k v/d on the Hann spectrum, searched over [v_min_kmh, v_max_kmh]) or
    "peaks" (v = d / the median interval of axle peaks at least ``min_interval_s`` apart). A
    dict: speed_kmh, uncertainty_kmh, frequency_hz, n_used."""
    return _viaduct.identify_speed(x, fs_hz, distance_m, method, v_min_kmh, v_max_kmh, harmonics, min_interval_s)


def fit(scenario, params, records=(), map=None, speed_kmh=(), train="", modes=None, modes_method=None, weights=None,
        starts=None, max_iterations=None, max_time_s=None, spectral_start=True, threads=1, out=None, progress=None):
    """Model updating, as ``viaduct fit``: scenario keys fitted within bounds so that the model
    reproduces measured records and identified modes (Levenberg-Marquardt with bounds, Ceres).

    params   {key: (lower, upper)} or {key: (lower, upper, "log" | "linear")}, starting from the
             scenario's values (scenario.set them first to start elsewhere)
    records  record files; ``map`` {channel: station} applies to each (also {response: station}
             for identified shapes); ``speed_kmh`` one speed or one per record; ``train`` a name
    modes    modal-fit or decay output (directory or file) for the modal and damping objectives
    weights  {objective: w}: time, peak, envelope, spectrum, modal, damping
    out      a directory for the CLI's files (fit.csv, fitted.toml, ...); None: none written
    progress callable(start, stage, iteration, cost, values) after iterations

    A dict: status ("converged", ...), message, "params" (key, unit, initial, estimate,
    std_error, sensitivity, at_bound, determined: a table), correlation, warnings, shift_s,
    cost_initial, cost_final, iterations, simulations, wall_s, modal_pairs. Ctrl-C stops the
    simulations and raises KeyboardInterrupt."""
    specs = []
    for key, bounds in params.items():
        if len(bounds) not in (2, 3):
            raise InputError(f"params['{key}']: expected (lower, upper) or (lower, upper, scale)")
        specs.append(f"{key}={bounds[0]!r}:{bounds[1]!r}" + (f":{bounds[2]}" if len(bounds) == 3 else ""))
    if out is not None:
        import os
        os.makedirs(out, exist_ok=True)
    speeds = [float(speed_kmh)] if isinstance(speed_kmh, (int, float)) else [float(v) for v in speed_kmh]
    r = _viaduct.fit(scenario._flat, specs, [str(p) for p in records], [f"{k}={v}" for k, v in (map or {}).items()], speeds,
                     train, None if modes is None else str(modes), modes_method,
                     [f"{k}={v!r}" for k, v in (weights or {}).items()], starts, max_iterations, max_time_s,
                     spectral_start, threads, None if out is None else str(out), progress)
    r["params"] = _table(r["params"])
    return r
