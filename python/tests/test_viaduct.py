"""The Python package against the CLI's own files for the same inputs, and its errors."""
import csv
import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import viaduct


def run_cli(cli, *args, code=0):
    p = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    assert p.returncode == code, p.stderr
    return p


def read_csv(path):
    """Columns of a CSV file (skipping '#' lines): numbers as float arrays, text as lists."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    header, body = rows[0], rows[1:]
    out = {}
    for j, name in enumerate(header):
        cells = [r[j] for r in body]
        try:
            out[name] = np.array([float(c) for c in cells])
        except ValueError:
            out[name] = cells
    return out


def close_to_printed(values, printed, digits):
    """Equal to the CSV's numbers printed with `digits` significant digits (%.{digits}g)."""
    values = np.asarray(values, dtype=float)
    np.testing.assert_allclose(values, printed, rtol=10.0 ** (1 - digits), atol=1e-300)


# Scenarios ---------------------------------------------------------------------------------------

def test_scenario_get_set_and_the_cli_messages(src, cli, tmp_path):
    sc = viaduct.load_scenario(src / "scenarios/hslm-simply-supported.toml")
    assert isinstance(sc.get("bridge.damping.ratio"), float) and isinstance(sc.get("train.files"), list)
    sc.set("sweep.speed_step_kmh", 20.0)
    assert sc.get("sweep.speed_step_kmh") == 20.0
    assert sc.where("sweep.speed_step_kmh")[0] == "--set"
    assert "sweep.speed_step_kmh = 20.0   # [km/h] --set" in sc.describe()  # as viaduct check prints it
    with pytest.raises(viaduct.InputError) as e:
        sc.set("bridge.EI", -1.0)
    cli_error = run_cli(cli, "check", src / "scenarios/hslm-simply-supported.toml", "--set", "bridge.EI=-1.0", code=2).stderr
    assert str(e.value) in cli_error  # the same text
    assert sc.get("bridge.EI") > 0  # a refused value leaves the scenario as it was
    with pytest.raises(viaduct.InputError, match="unknown key.*did you mean"):
        sc.set("bridge.EJ", 1.0)
    with pytest.raises(ValueError):  # InputError is a ValueError
        viaduct.load_scenario(src / "scenarios/no-such-file.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[bridge]\nspan_lengths = [15.0]\nEI = -1.0\n")
    with pytest.raises(viaduct.InputError, match=r"bad\.toml:3: key 'bridge\.EI': must be > 0"):
        viaduct.load_scenario(bad)


def test_scenario_from_a_dict_is_the_file(src, monkeypatch):
    monkeypatch.chdir(src)  # relative paths of a dict are from the working directory
    d = {"bridge": {"span_lengths": [15.0], "EI": 7.694e9, "mass_per_m": 15000.0, "damping": {"ratio": 0.0135}},
         "train": {"files": ["hslm:A1"]},
         "stations": [{"name": "mid", "span": 1, "at": 0.5}],
         "sweep": {"speeds_kmh": [200.0, 300.0]}}
    sc = viaduct.scenario_from_dict(d)
    assert sc.get("stations[0].name") == "mid"
    assert sc.get("bridge.EI") == 7.694e9
    env = viaduct.sweep(sc)
    assert list(env["speed_kmh"]) == [200.0, 300.0]
    with pytest.raises(viaduct.InputError, match="bridge.mass_per_m"):
        viaduct.scenario_from_dict({**d, "bridge": {**d["bridge"], "mass_per_m": 0.0}})


# Runs and sweeps ---------------------------------------------------------------------------------

def test_run_equals_history_csv(src, cli, tmp_path):
    sc = viaduct.load_scenario(src / "scenarios/hslm-simply-supported.toml")
    h = viaduct.run(sc, speed_kmh=300, train="HSLM-A4")
    run_cli(cli, "run", src / "scenarios/hslm-simply-supported.toml", "--speed-kmh", 300, "--train", "HSLM-A4", "-q",
            "--out", tmp_path)
    ref = read_csv(tmp_path / "history.csv")
    assert list(h.keys()) == list(ref.keys())
    np.testing.assert_allclose(h["t_s"], ref["t_s"], atol=5e-7)
    for name in list(ref)[1:]:
        close_to_printed(h[name], ref[name], 9)
    assert h.attrs["train"] == "HSLM-A4" and h.attrs["speed_kmh"] == pytest.approx(300)


def test_sweep_equals_envelope_csv_and_threads_agree(src, cli, tmp_path):
    scenario = src / "scenarios/old-guadiana-sensitivity.toml"
    sc = viaduct.load_scenario(scenario, set={"sweep.n_speeds": 3, "sweep.variants[1].factors": [0.0, 1.0]})
    calls = []
    env = viaduct.sweep(sc, threads=2, progress=lambda done, total: calls.append((done, total)))
    run_cli(cli, "sweep", scenario, "--set", "sweep.n_speeds=3", "--set", "sweep.variants[1].factors=[0.0, 1.0]", "-q",
            "--threads", 2, "--out", tmp_path, code=0)
    ref = read_csv(tmp_path / "envelope.csv")
    assert list(env.columns) == list(ref.keys())  # the CLI's names and order
    for name, col in ref.items():
        if isinstance(col, list):
            assert list(env[name]) == col
        else:
            close_to_printed(env[name], col, 10)
    assert calls and calls[-1][0] <= calls[-1][1]
    one = viaduct.sweep(sc, threads=1)
    assert np.array_equal(one["max_abs_acc_mps2"].to_numpy(), env["max_abs_acc_mps2"].to_numpy())  # bit for bit
    gov = read_csv(tmp_path / "governing.csv")
    close_to_printed(env.attrs["governing"]["max_abs_acc_mps2"], gov["max_abs_acc_mps2"], 10)
    assert len(env.attrs["failures"]) == 0


def test_load_effects_and_vehicles_equal_the_cli(src, cli, tmp_path):
    hslm = src / "scenarios/hslm-simply-supported.toml"
    sc = viaduct.load_scenario(hslm, set={"sweep.speed_step_kmh": 70.0})
    env = viaduct.sweep(sc, threads=2, load_effects=True)
    run_cli(cli, "sweep", hslm, "--set", "sweep.speed_step_kmh=70.0", "--load-effects", "-q", "--out", tmp_path / "le")
    ref = read_csv(tmp_path / "le/load_effects.csv")
    le = env.attrs["load_effects"]
    assert list(le.columns) == list(ref.keys())
    for name, col in ref.items():
        if isinstance(col, list):
            assert list(le[name]) == col
        else:
            close_to_printed(le[name], col, 10)
    veh = src / "scenarios/vehicles-25m.toml"
    env = viaduct.sweep(viaduct.load_scenario(veh, set={"sweep.speed_step_kmh": 120.0}), threads=2)
    run_cli(cli, "sweep", veh, "--set", "sweep.speed_step_kmh=120.0", "-q", "--out", tmp_path / "veh")
    ref = read_csv(tmp_path / "veh/vehicles.csv")
    v = env.attrs["vehicles"]
    assert list(v.columns) == list(ref.keys())
    assert [str(x).lower() for x in v["contact_lost"]] == ref["contact_lost"]
    close_to_printed(v["min_contact_N"], ref["min_contact_N"], 10)
    close_to_printed(v["max_body_acc_mps2"], ref["max_body_acc_mps2"], 10)
    h = viaduct.run(viaduct.load_scenario(veh))
    run_cli(cli, "run", veh, "-q", "--out", tmp_path / "vrun")
    ref = read_csv(tmp_path / "vrun/vehicles.csv")
    vh = h.attrs["vehicles"]
    assert list(vh.columns) == list(ref.keys())
    for name in list(ref)[1:]:
        close_to_printed(vh[name], ref[name], 10)


def test_sweep_failures_and_tables_without_pandas(src, monkeypatch):
    sc = viaduct.load_scenario(src / "scenarios/old-guadiana-sensitivity.toml",
                               set={"sweep.n_speeds": 2, "sweep.variants[0].factors": [0.0, 1.0]})
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas fails
    with pytest.warns(UserWarning, match="sweep: 2 cases failed and are not in the envelope"):
        env = viaduct.sweep(sc)
    assert isinstance(env, dict) and isinstance(env["max_abs_acc_mps2"], np.ndarray)
    assert len(env["failures"]["error"]) == 2 and "factor 0 breaks the rule" in env["failures"]["error"][0]


def test_ctrl_c_stops_a_sweep_and_the_gil_is_free(src):
    sc = viaduct.load_scenario(src / "scenarios/old-guadiana-sensitivity.toml")
    seen = []
    # Ctrl-C half a second in: KeyboardInterrupt, with most cases never run.
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        viaduct.sweep(sc, threads=1, progress=lambda d, n: seen.append((d, n)))
    # Stopped early (under load the signal may come before the first case is done: no progress yet).
    assert not seen or seen[-1][0] < seen[-1][1]
    # Ctrl-C stops a single run inside its time stepping: a 240 000-step passage interrupted 0.3 s
    # in ends in a fraction of the time it takes whole (both timed here, under the same load).
    long_run = viaduct.load_scenario(src / "scenarios/old-guadiana-talgo.toml",
                                     set={"analysis.dt": 1e-4, "analysis.free_vibration_s": 20.0})
    t0 = time.perf_counter()
    viaduct.run(long_run)
    whole = time.perf_counter() - t0
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        viaduct.run(long_run)
    assert time.perf_counter() - t0 < 0.5 * whole
    assert len(viaduct.run(viaduct.load_scenario(src / "scenarios/old-guadiana-talgo.toml"))["t_s"]) > 0  # cleared
    # Another Python thread runs while a sweep computes.
    ticks = 0
    small = viaduct.load_scenario(src / "scenarios/old-guadiana-sensitivity.toml", set={"sweep.n_speeds": 6})
    worker = threading.Thread(target=viaduct.sweep, args=(small,))
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.01)
    assert ticks > 20  # the sweep takes about a second: the GIL was released


# Records and signals -----------------------------------------------------------------------------

def test_ctrl_c_in_a_progress_callback_and_cancellation_per_call(src):
    # A SIGINT while the progress callback runs raises KeyboardInterrupt; so does an exception out
    # of the callback. The cancellation is the call's: a sweep on another thread at the same time
    # runs to its end (issue #36: the request was process-wide and cut another thread's sweep).
    path = os.path.join(src, "scenarios/hslm-simply-supported.toml")
    sc = viaduct.load_scenario(path, set={"sweep.speed_step_kmh": 10.0})

    def interrupt(done, total):
        if done >= 2:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.2)

    with pytest.raises(KeyboardInterrupt):
        viaduct.sweep(sc, threads=1, progress=interrupt)

    results = {}

    def other():
        results["other"] = viaduct.sweep(sc, threads=1)

    def stopped(done, total):
        raise KeyboardInterrupt

    t = threading.Thread(target=other)
    t.start()
    with pytest.raises(KeyboardInterrupt):
        viaduct.sweep(sc, threads=1, progress=stopped)
    t.join()
    full = viaduct.sweep(sc, threads=1)
    assert len(results["other"]) == len(full)
    failures = results["other"].attrs["failures"]
    assert (len(failures) if hasattr(failures, "columns") else len(failures["variant"])) == 0


def test_input_checks_of_the_signal_functions():
    # Non-finite samples, complex arrays and a one-sample spectrum are input errors (issue #36).
    x = np.sin(np.linspace(0, 20, 400))
    bad = x.copy()
    bad[17] = np.nan
    with pytest.raises(viaduct.InputError, match="non-finite"):
        viaduct.filter(bad, 100.0, 1.0, 20.0)
    with pytest.raises(viaduct.InputError, match="complex"):
        viaduct.filter(x + 1j * x, 100.0, 1.0, 20.0)
    with pytest.raises(viaduct.InputError, match="complex"):
        viaduct.spectrum(x.astype(complex), 100.0)
    with pytest.raises(viaduct.InputError, match="at least 2 samples"):
        viaduct.spectrum(np.array([1.0]), 100.0)


def test_a_key_with_a_line_break_sets_nothing(src):
    # set("analysis.dt=0.002\nanalysis.alpha", -0.1) once set a second key (issue #36).
    sc = viaduct.load_scenario(src / "scenarios/hslm-simply-supported.toml")
    with pytest.raises(viaduct.InputError, match="line break"):
        sc.set("analysis.dt=0.002\nanalysis.alpha", -0.1)
    assert sc.get("analysis.dt") == 0.001 and sc.get("analysis.alpha") == 0.0


def test_read_record_per_channel_nan_and_header_options(src, tmp_path):
    # A long NaN run stays in its channel (the CLI's reader, issue #39); the header options work.
    lines = ["t_s,a_m,b_mps2"] + ["%.3f,%.6f,%s" % (k / 100, k * 1e-3, "NaN" if 20 <= k < 40 else "%.6f" % (k * 1e-2)) for k in range(100)]
    (tmp_path / "nan.csv").write_text("\n".join(lines) + "\n")
    rec = viaduct.read_record(tmp_path / "nan.csv")
    assert rec.data.shape == (100, 2)
    assert not np.isnan(rec["a_m"]).any()
    assert np.isnan(rec["b_mps2"]).sum() == 20
    logger = src / "tests/data/loggers/preamble-datetime.csv"
    assert viaduct.read_record(logger).data.shape == (300, 2)
    assert viaduct.read_record(logger, header_line=6).data.shape == (300, 2)
    assert viaduct.read_record(logger, skip_lines=5).data.shape == (300, 2)
    with pytest.raises(viaduct.InputError):
        viaduct.read_record(logger, header_line=-1)


def test_read_record_every_format(src):
    csv_rec = viaduct.read_record(src / "data/records/synthetic-deck.csv")
    ref = read_csv(src / "data/records/synthetic-deck.csv")
    assert csv_rec.channels == [c for c in ref if c != "t_s"]
    np.testing.assert_array_equal(csv_rec[csv_rec.channels[0]], ref[csv_rec.channels[0]])
    np.testing.assert_allclose(csv_rec.t, ref["t_s"], atol=1e-9)
    assert csv_rec.data.base is not None and not csv_rec.data.flags.owndata  # the reader's memory
    assert np.shares_memory(csv_rec.data, csv_rec[csv_rec.channels[0]])
    mat = viaduct.read_record(src / "tests/data/records/matrix.mat")
    assert mat.data.shape[0] > 0 and mat.fs_hz > 0
    uff = viaduct.read_record(src / "tests/fuzz/corpus/uff/two-channels.uff")
    assert uff.data.shape[1] == 2
    with pytest.raises(viaduct.InputError, match="no channel 'nope' in the record; it has: deck_disp_m, deck_acc_mps2"):
        csv_rec["nope"]
    with pytest.raises(viaduct.InputError, match="no-such.csv"):
        viaduct.read_record(src / "data/records/no-such.csv")


def test_filter_spectrum_welch_equal_the_cli(src, cli, tmp_path):
    path = src / "data/records/synthetic-deck.csv"
    rec = viaduct.read_record(path)
    ch = rec.channels[0]
    x = rec[ch]
    y = viaduct.filter(x, rec.fs_hz, low_hz=1.0, high_hz=30.0)
    run_cli(cli, "filter", path, "--low-hz", 1, "--high-hz", 30, "-q", "--out", tmp_path / "f")
    close_to_printed(y, read_csv(tmp_path / "f/filtered.csv")[ch], 9)
    assert y.base is not None and not y.flags.owndata  # handed over, not copied
    f, a = viaduct.spectrum(x, rec.fs_hz)
    run_cli(cli, "spectrum", path, "-q", "--out", tmp_path / "s")
    ref = read_csv(tmp_path / "s/spectrum.csv")
    close_to_printed(f, ref["frequency_hz"], 9)
    close_to_printed(a, ref[[k for k in ref if k != "frequency_hz"][0]], 9)
    fw, p = viaduct.welch(x, rec.fs_hz, nperseg=1024)
    run_cli(cli, "spectrum", path, "--welch", "--nperseg", 1024, "-q", "--out", tmp_path / "w")
    ref = read_csv(tmp_path / "w/spectrum.csv")
    close_to_printed(p, ref[[k for k in ref if k != "frequency_hz"][0]], 9)
    with pytest.raises(viaduct.InputError, match="high_hz|Nyquist|fs"):
        viaduct.filter(x, rec.fs_hz, low_hz=1.0, high_hz=rec.fs_hz)
    with pytest.raises(viaduct.InputError, match="1-D"):
        viaduct.filter(rec.data, rec.fs_hz)


def test_compare_equals_the_cli(src, cli, tmp_path):
    scenario = src / "scenarios/old-guadiana-talgo.toml"
    rec = viaduct.read_record(src / "data/records/synthetic-deck.csv")
    h = viaduct.run(viaduct.load_scenario(scenario))  # run.speed_kmh = 154.8
    t = np.asarray(h["t_s"])
    c = viaduct.compare(rec["deck_acc_mps2"], rec.fs_hz, h["S1_mid_acc_mps2"], 1.0 / (t[1] - t[0]), t0_record=rec.t0_s)
    run_cli(cli, "compare", scenario, "--record", src / "data/records/synthetic-deck.csv", "--map", "deck_acc=S1_mid", "-q",
            "--out", tmp_path)
    ref = read_csv(tmp_path / "compare_metrics.csv")
    for k in ["shift_s", "peak_record", "peak_model", "peak_ratio", "rms_ratio", "correlation", "f_peak_record_hz",
              "f_peak_model_hz", "spectral_correlation"]:
        close_to_printed([c[k]], ref[k], 8)
    overlay = read_csv(tmp_path / "compare_time.csv")
    close_to_printed(c["model"], overlay["deck_acc_model_mps2"], 9)
    assert c["unit_warning"] == ""
    # The record in g read as m/s²: the same warning as the CLI's.
    g = viaduct.compare(rec["deck_acc_mps2"] / 9.80665, rec.fs_hz, h["S1_mid_acc_mps2"], 1.0 / (t[1] - t[0]), t0_record=rec.t0_s)
    assert "the factor between g and m/s²" in g["unit_warning"]
    with pytest.raises(viaduct.InputError):
        viaduct.compare(rec["deck_acc_mps2"][:5], rec.fs_hz, h["S1_mid_acc_mps2"], 1000.0)


def test_frf_modal_fit_and_decay_equal_the_cli(src, cli, tmp_path):
    # A swept-sine test of the HSLM 15 m span, as the CLI's samples make it.
    run_cli(cli, "shaker", src / "scenarios/hslm-simply-supported.toml", "--force-at", 7, "--swept", "2:30", "--sweep-s", 60,
            "--snr-db", 40, "-q", "--out", tmp_path / "sweep")
    run_cli(cli, "frf", tmp_path / "sweep/record.csv", "--force", "force_N", "--method", "swept", "--f-min", 3, "--f-max", 28,
            "-q", "--out", tmp_path / "frf")
    rec = viaduct.read_record(tmp_path / "sweep/record.csv")
    f = viaduct.record_frf(rec, "force_N", method="swept", f_min_hz=3.0, f_max_hz=28.0)
    ref = read_csv(tmp_path / "frf/frf.csv")
    assert f["responses"] == ["mid"] and f["units"] == ["mps2"]
    close_to_printed(f["frequency_hz"], ref["frequency_hz"], 10)
    close_to_printed(f["h"][:, 0].real, ref["mid_re_mps2_per_N"], 10)
    close_to_printed(f["h"][:, 0].imag, ref["mid_im_mps2_per_N"], 10)
    # The modal fit of the CLI's FRF file.
    run_cli(cli, "modal-fit", tmp_path / "frf/frf.csv", "--f-min", 3, "--f-max", 28, "--max-order", 30, "-q",
            "--out", tmp_path / "fit")
    fit = viaduct.modal_fit(viaduct.read_frf(tmp_path / "frf/frf.csv"), f_min_hz=3.0, f_max_hz=28.0, max_order=30)
    modes = read_csv(tmp_path / "fit/modes.csv")
    assert list(fit["modes"]["method"]) == modes["method"]
    close_to_printed(fit["modes"]["frequency_hz"], modes["frequency_hz"], 8)
    close_to_printed(fit["modes"]["damping_ratio"], modes["damping_ratio"], 8)
    stab = read_csv(tmp_path / "fit/stabilization.csv")
    assert list(fit["stabilization"]["status"]) == stab["status"]
    # A free decay after a passage.
    run_cli(cli, "run", src / "scenarios/old-guadiana-talgo.toml", "--set", "analysis.free_vibration_s=5", "-q",
            "--out", tmp_path / "passage")
    run_cli(cli, "decay", tmp_path / "passage/history.csv", "--channel", "S1_mid_acc", "--frequency-hz", 10, "-q",
            "--out", tmp_path / "decay")
    hist = viaduct.read_record(tmp_path / "passage/history.csv")
    d = viaduct.decay(hist["S1_mid_acc_mps2"], hist.fs_hz, 10.0, t0_s=hist.t0_s)
    ref = read_csv(tmp_path / "decay/decay.csv")
    for k in ["start_s", "frequency_hz", "zeta_log_decrement", "zeta_envelope_fit", "zeta_hilbert", "amplitude_start",
              "law_zeta0", "law_f0_hz"]:
        close_to_printed([d[k]], ref[k], 8)
    amp = read_csv(tmp_path / "decay/decay_amplitude.csv")
    close_to_printed(d["by_amplitude"]["damping_ratio"], amp["damping_ratio"], 8)
    with pytest.raises(viaduct.InputError, match="m, mps or mps2|unit"):
        viaduct.frf(rec["force_N"], rec["mid_acc_mps2"], rec.fs_hz, ["g"])


def test_oma_equals_the_cli(src, cli, tmp_path):
    # The free vibration after a passage over the Old Guadiana model, decimated to 100 Hz.
    run_cli(cli, "run", src / "scenarios/old-guadiana-talgo.toml", "--set", "analysis.free_vibration_s=8", "-q",
            "--out", tmp_path / "passage")
    chans = ["S1_mid_acc", "S1_3L4_acc", "S2_mid_acc"]
    run_cli(cli, "oma", tmp_path / "passage/history.csv", "--free-decay", *sum([["--channel", c] for c in chans], []),
            "--f-min-hz", 2, "--f-max-hz", 40, "--decimate", 10, "-q", "--out", tmp_path / "oma")
    hist = viaduct.read_record(tmp_path / "passage/history.csv")
    y = np.column_stack([hist[c + "_mps2"] for c in chans])
    w = viaduct.oma(y, hist.fs_hz, t0_s=hist.t0_s, names=chans, f_min_hz=2.0, f_max_hz=40.0, free_decay=True, decimate=10)
    assert len(w) == 1 and w[0]["error"] == "" and w[0]["warning"] == ""
    # The whole passage taken as ambient: a burst, said and warned of.
    with pytest.warns(UserWarning, match="not stationary"):
        amb = viaduct.oma(y, hist.fs_hz, names=chans, f_min_hz=2.0, f_max_hz=40.0, decimate=10, min_periods=10)
    assert "a train passage or another burst" in amb[0]["warning"]
    with open(tmp_path / "oma/modes.csv", newline="") as f:
        modes = [r for r in csv.DictReader(f) if r["method"] == "ssi-cov"]
    assert len(modes) == len(w[0]["modes"]["frequency_hz"]) >= 1
    close_to_printed(w[0]["modes"]["frequency_hz"], [float(r["frequency_hz"]) for r in modes], 8)
    close_to_printed(w[0]["modes"]["damping_ratio"], [float(r["damping_ratio"]) for r in modes], 8)
    stab = read_csv(tmp_path / "oma/stabilization.csv")
    assert list(w[0]["poles"]["status"]) == stab["status"]
    # Tracking two windows of the same record: the same tracks.
    assert viaduct.track_modes([w[0], w[0]]) == [list(range(len(modes)))] * 2
    # A window that cannot be identified says why in its "error" (the others stand), and warns.
    with pytest.warns(UserWarning, match="at least 2 channels"):
        bad = viaduct.oma(y[:, :1], hist.fs_hz, free_decay=True, decimate=10)
    assert "at least 2 channels" in bad[0]["error"]
    with pytest.raises(TypeError, match="unexpected keyword"):
        viaduct.oma(y, hist.fs_hz, tol_frequenzy=0.01)


def test_peaks_and_speed(src, cli, tmp_path):
    rec = viaduct.read_record(src / "data/records/synthetic-deck.csv")
    x = rec["deck_acc_mps2"]
    p = viaduct.peaks(x, min_prominence=0.05, interpolation="none")
    try:
        import scipy.signal
    except ImportError:
        pytest.skip("scipy for the reference")
    idx, props = scipy.signal.find_peaks(x, prominence=0.05)
    assert list(p["index"]) == list(idx)
    np.testing.assert_allclose(p["prominence"], props["prominences"], rtol=1e-12)  # differences of the same samples: rounding only
    s = viaduct.identify_speed(x, rec.fs_hz, 13.14, v_min_kmh=100, v_max_kmh=250)
    run_cli(cli, "speed", src / "data/records/synthetic-deck.csv", "--channel", "deck_acc_mps2", "--distance-m", 13.14,
            "--v-min-kmh", 100, "--v-max-kmh", 250, "-q", "--out", tmp_path)
    ref = read_csv(tmp_path / "speed.csv")
    close_to_printed([s["speed_kmh"], s["uncertainty_kmh"]], [ref["speed_kmh"][0], ref["uncertainty_kmh"][0]], 8)
    assert abs(s["speed_kmh"] - 154.8) < 3 * s["uncertainty_kmh"]  # the record's known speed
    with pytest.raises(viaduct.InputError, match="spectrum or peaks"):
        viaduct.identify_speed(x, rec.fs_hz, 13.14, method="comb")


def test_fit_equals_the_cli(src, cli, tmp_path):
    scenario = src / "scenarios/hslm-simply-supported.toml"
    run_cli(cli, "run", scenario, "--speed-kmh", 300, "--train", "HSLM-A4", "-q", "--out", tmp_path / "a4")
    run_cli(cli, "fit", scenario, "--record", tmp_path / "a4/history.csv", "--map", "mid_acc_mps2=mid", "--train", "HSLM-A4",
            "--speed-kmh", 300, "--param", "bridge.EI=5e9:1e10", "--param", "bridge.damping.ratio=0.005:0.05",
            "--set", "bridge.EI=7e9", "--set", "bridge.damping.ratio=0.02", "--threads", 2, "-q", "--out", tmp_path / "cli")
    sc = viaduct.load_scenario(scenario, set={"bridge.EI": 7e9, "bridge.damping.ratio": 0.02})
    iterations = []
    r = viaduct.fit(sc, {"bridge.EI": (5e9, 1e10), "bridge.damping.ratio": (0.005, 0.05)},
                    records=[tmp_path / "a4/history.csv"], map={"mid_acc_mps2": "mid"}, train="HSLM-A4", speed_kmh=300,
                    threads=2, out=tmp_path / "py", progress=lambda *a: iterations.append(a))
    ref = read_csv(tmp_path / "cli/fit.csv")
    assert r["status"] == "converged" and list(r["params"]["key"]) == ref["key"]
    close_to_printed(r["params"]["estimate"], ref["estimate"], 10)
    close_to_printed(r["params"]["std_error"], ref["std_error"], 10)
    assert all(r["params"]["determined"])
    assert abs(r["params"]["estimate"][0] / 7.694e9 - 1) < 1e-6  # the record's own model
    assert (tmp_path / "py/fitted.toml").exists() and iterations
    with pytest.raises(viaduct.InputError, match="bridge.EJ"):
        viaduct.fit(sc, {"bridge.EJ": (1.0, 2.0)}, records=[tmp_path / "a4/history.csv"], map={"mid_acc_mps2": "mid"})


def test_passages_equal_the_cli(src, cli, tmp_path):
    # viaduct.passages runs the CLI's workflow (io::run_passages): the same four tables byte for
    # byte, with a record that cannot be read kept as a failure while the others complete.
    d = src / "data/records/passages"
    table = tmp_path / "passages.csv"
    table.write_text((d / "passages.csv").read_text().replace("passage-", str(d) + "/passage-")
                     .replace("../../trains/", str(src / "data/trains") + "/") + "missing.csv,HSLM-A1,,\n")
    scenario = src / "scenarios/hslm-simply-supported.toml"
    sets = {"analysis.method": "modal", "sweep.speed_step_kmh": 20.0}
    run_cli(cli, "passages", scenario, "--records", table, "--map", "mid_acc=mid", "--map", "mid_disp=mid",
            "--set", "analysis.method=\"modal\"", "--set", "sweep.speed_step_kmh=20", "-q", "--out", tmp_path / "cli", code=1)
    seen = []
    with pytest.warns(UserWarning, match="failed: .*missing.csv"):  # what the CLI exits 1 for is not silent
        r = viaduct.passages(viaduct.load_scenario(scenario, set=sets), table, {"mid_acc": "mid", "mid_disp": "mid"}, threads=2,
                             out=tmp_path / "py", progress=lambda done, total: seen.append((done, total)))
    for name in ("passages.csv", "passages_summary.csv", "model_envelope.csv", "failures.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    ref = read_csv(tmp_path / "cli/passages.csv")
    assert list(r["passage"]) == ref["passage"] and len(ref["passage"]) == 6  # three passages x two channels
    close_to_printed(r["ratio"], ref["ratio"], 8)
    assert [bool(w) for w in r["within"]] == [w == "true" for w in ref["within"]]
    info = r.attrs if hasattr(r, "attrs") else r["attrs"]
    assert info["n_passages"] == 4 and info["n_failed"] == 1
    assert len(info["failures"]["passage"]) == 1 and list(info["failures"]["passage"])[0].endswith("missing.csv")
    assert seen and seen[-1][0] == seen[-1][1]
    import tomllib
    with open(tmp_path / "cli/manifest.toml", "rb") as f:
        manifest = tomllib.load(f)
    # the manifest's warnings are Python's (which add what reading the records repaired)
    assert set(manifest["run"].get("warnings", [])) <= set(info["warnings"])
    with pytest.raises(viaduct.InputError, match="no station 'S9'"):
        viaduct.passages(viaduct.load_scenario(scenario), table, {"mid_acc": "S9"})


def test_sampled_sweep_equals_the_cli_and_resumes_after_ctrl_c(src, cli, tmp_path):
    # viaduct.sampled_sweep runs the CLI's io::run_sampled: cut by Ctrl-C after its first batch of
    # samples, it leaves the whole batches before it, and resumed it writes the CLI's files.
    og = src / "scenarios/old-guadiana-sampled.toml"
    run_cli(cli, "sweep", og, "--set", "sweep.n_samples=3", "--set", "sweep.n_speeds=2", "--set", "sweep.batch=1", "-q",
            "--out", tmp_path / "cli")
    sc = viaduct.load_scenario(og, set={"sweep.n_samples": 3, "sweep.n_speeds": 2, "sweep.batch": 1})

    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        viaduct.sampled_sweep(sc, tmp_path / "py", progress=stop)
    assert (tmp_path / "py/sample_progress.toml").exists() and not (tmp_path / "py/peak_percentiles.csv").exists()
    t = viaduct.sampled_sweep(sc, tmp_path / "py", resume=True)
    for name in ("samples.csv", "sample_peaks.csv", "failures.csv", "percentiles.csv", "peak_percentiles.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    info = t.attrs if hasattr(t, "attrs") else t["attrs"]
    assert info["n_samples_total"] == 3 and info["n_failed_run"] == 0 and 0 < info["n_samples_run"] < 3
    assert len(info["sample_peaks"]["sample"]) == len(read_csv(tmp_path / "cli/sample_peaks.csv")["sample"])
    with pytest.raises(viaduct.InputError, match="sampled_sweep"):  # sweep() on a sampled study points here
        viaduct.sweep(sc)
    with pytest.raises(viaduct.InputError, match="not a sampled study"):
        viaduct.sampled_sweep(viaduct.load_scenario(src / "scenarios/hslm-simply-supported.toml"), tmp_path / "no")


def test_cmake_install_puts_an_importable_package(tmp_path):
    build = os.environ.get("VIADUCT_BUILD")
    if not build:
        pytest.skip("VIADUCT_BUILD: the build tree (set by CTest)")
    subprocess.run(["cmake", "--install", build, "--prefix", str(tmp_path)], check=True, capture_output=True)
    site = tmp_path / f"lib/python{sys.version_info.major}.{sys.version_info.minor}/dist-packages"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    p = subprocess.run([sys.executable, "-c", "import viaduct; print(viaduct.__file__, viaduct.version())"], env=env,
                       capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith(str(site))


def test_the_example_runs(src, tmp_path):
    p = subprocess.run([sys.executable, str(src / "examples/python/sweep_and_record.py"), "--out", str(tmp_path)],
                       capture_output=True, text=True, cwd=src)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "envelope.png").stat().st_size > 10000
    assert (tmp_path / "record.png").stat().st_size > 10000


def test_assess_equals_the_cli(src, cli, tmp_path):
    # viaduct.assess runs the CLI's plan, runs and checks (io/study assessment): the same checks.
    path = src / "scenarios/hslm-simply-supported.toml"
    sets = {"assess.speed_step_kmh": 40.0, "assess.refine_band": 0.0}
    run_cli(cli, "assess", path, "--set", "assess.speed_step_kmh=40", "--set", "assess.refine_band=0", "--no-plots", "--no-pdf",
            "--out", tmp_path / "cli", "-q")
    checks = viaduct.assess(viaduct.load_scenario(path, set=sets), threads=2, out=tmp_path / "py")
    with open(tmp_path / "cli/checks.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(checks["check"])
    for i, row in enumerate(rows):
        assert row["check"] == list(checks["check"])[i] and row["result"] == list(checks["result"])[i]
        assert row["unit"] == list(checks["unit"])[i]
        # a "not checked (2D model)" row has no value: an empty cell in the CSV, NaN in Python
        value, py_value = float(row["value"] or "nan"), float(list(checks["value"])[i])
        assert (math.isnan(value) and math.isnan(py_value)) or value == pytest.approx(py_value, rel=1e-9)
    info = checks.attrs if hasattr(checks, "attrs") else checks["attrs"]
    assert info["cutoff_hz"] > 30.0 and "# Dynamic assessment" in info["report"]
    for name in ("checks.csv", "phi_dyn.csv", "envelope.csv", "load_effects.csv"):  # out= writes the CLI's files
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_fatigue_mix_equals_the_cli(src, cli, tmp_path):
    # Annex D's light mix over the 15 m span: the CLI's damage.csv and cycles.csv, cell for cell.
    sc = viaduct.load_scenario(src / "scenarios/hslm-simply-supported.toml")
    sc.set("analysis.method", "modal")
    mix = src / "data/trains/fatigue/mix-light.toml"
    seen = []
    d = viaduct.fatigue_mix(sc, mix, "mid_moment", detail=71, section_modulus_m3=0.05, threads=2,
                            progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (4, 4)  # the four trains, done
    run_cli(cli, "fatigue", src / "scenarios/hslm-simply-supported.toml", "--set", 'analysis.method="modal"', "--mix", mix,
            "--channel", "mid_moment", "--detail", 71, "--section-modulus-m3", 0.05, "-q", "--out", tmp_path / "m")
    for table, name in ((d, "damage.csv"), (d.attrs["cycles"], "cycles.csv")):
        ref = read_csv(tmp_path / "m" / name)
        assert list(ref) == list(table.columns)
        for col, want in ref.items():
            got = list(table[col])
            if isinstance(got[0], str):
                assert got == list(want), col
            else:  # numbers, an empty cell NaN (8 significant digits in the file)
                want = np.array([float(c) if c != "" else np.nan for c in want], dtype=float)
                assert np.allclose(np.asarray(got, dtype=float), want, rtol=1e-7, atol=0, equal_nan=True), col
    assert list(d["train"]) == ["type1", "type2", "type5", "type9", "total"]
    assert d.attrs["damage_per_year"] == pytest.approx(d["damage_per_year"].iloc[-1], rel=1e-7)
    assert d.attrs["n_failed"] == 0
    with pytest.raises(viaduct.InputError, match="no such load effect"):
        viaduct.fatigue_mix(sc, mix, "mid_shear", detail=71)
    with pytest.raises(viaduct.InputError, match="exactly one of --detail"):
        viaduct.fatigue_mix(sc, mix, "mid_moment", section_modulus_m3=0.05)


def test_rainflow_and_miner_damage_equal_the_cli(src, cli, tmp_path):
    # ASTM E1049's example, then a passage's strain: the CLI's damage from the same cycles.
    r, m, n = viaduct.rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2])
    counts = {}
    for rr, nn in zip(r, n):
        counts[rr] = counts.get(rr, 0.0) + nn
    assert counts == {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}
    assert list(viaduct.rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2], method="four-point")[0]) != []
    path = src / "data/records/passages/passage-01.csv"
    rec = viaduct.read_record(path)
    r, m, n = viaduct.rainflow(rec["mid_strain_ue"], hysteresis=1e6 / 210e9 * 1e6)  # 1 MPa in microstrain
    d = viaduct.miner_damage(r, n, detail=71, to_pa=210e9 * 1e-6)
    run_cli(cli, "fatigue", path, "--channel", "mid_strain", "--detail", 71, "--hysteresis-mpa", 1, "-q", "--out", tmp_path / "f")
    ref = read_csv(tmp_path / "f/damage.csv")
    assert abs(d - ref["damage"][0]) <= 1e-7 * ref["damage"][0]
    assert abs(n.sum() - ref["cycles"][0]) < 1e-9
    with pytest.raises(viaduct.InputError, match="three-point or four-point"):
        viaduct.rainflow([0, 1, 0], method="five-point")
    with pytest.raises(viaduct.InputError, match="not one of EN 1993-1-9's"):
        viaduct.miner_damage(r, n, detail=75)
    with pytest.raises(viaduct.InputError, match="exactly one of detail or delta_c_mpa"):
        viaduct.miner_damage(r, n)


def test_a_wrong_viaduct_simd_fails_the_import_as_it_stops_the_cli(src, cli, tmp_path):
    # The package checks VIADUCT_SIMD when imported (a sweep would otherwise retry its blocks on
    # the general path and say nothing); the CLI stops with exit 2. Both name the variable.
    env = dict(os.environ, VIADUCT_SIMD="avx3")
    p = subprocess.run([sys.executable, "-c", "import viaduct"], capture_output=True, text=True, env=env)
    assert p.returncode != 0
    assert "ImportError" in p.stderr and "VIADUCT_SIMD = 'avx3'" in p.stderr
    q = subprocess.run([cli, "check", str(src / "scenarios/hslm-simply-supported.toml")], capture_output=True,
                       text=True, env=env)
    assert q.returncode == 2 and "expected baseline, avx2 or avx512" in q.stderr
    ok = subprocess.run([sys.executable, "-c", "import viaduct"], capture_output=True, text=True,
                        env=dict(os.environ, VIADUCT_SIMD="baseline"))
    assert ok.returncode == 0, ok.stderr
