#!/usr/bin/env python3
"""Writes tests/data/loggers/: one record in the text layouts of six logger families, and the
preamble of issue #39, each holding the same two signals (tests/unit/io/test_logger_corpus.cpp):

    acceleration a(t) = 0.5 sin(2 pi 10 t) m/s^2,  strain e(t) = 30 sin(2 pi 2 t) + 12 microstrain,

t from the first sample. The layouts are written from the vendors' published descriptions (the
sources are in tests/data/loggers/README.md); the values in each file's own units and number
format. Run: python3 scripts/generate/make_logger_corpus.py [OUTDIR]
"""
import math
import os
import sys

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "tests", "data", "loggers")
G = 9.80665


def acc(t):
    return 0.5 * math.sin(2 * math.pi * 10.0 * t)


def strain(t):
    return 30.0 * math.sin(2 * math.pi * 2.0 * t) + 12.0


def num(v, comma=False, digits=7):
    s = f"{v:.{digits}g}"
    return s.replace(".", ",") if comma else s


def clock(seconds_of_day, frac_digits):
    h = int(seconds_of_day // 3600)
    m = int((seconds_of_day - 3600 * h) // 60)
    s = seconds_of_day - 3600 * h - 60 * m
    return f"{h:02d}:{m:02d}:{s:0{3 + frac_digits}.{frac_digits}f}"


def write(name, head, fs, row):
    """The file `name`: the lines of `head`, then row(k, t) for each sample (CRLF line ends)."""
    lines = head + [row(k, k / fs) for k in range(N)]
    with open(os.path.join(OUT, name), "w", encoding="utf-8", newline="") as f:
        f.write("\r\n".join(lines) + "\r\n")


N = 300
START = 14 * 3600 + 22 * 60 + 5.0  # 14:22:05 on 3 December 2026


def hbm_catman():
    # catman ASCII export: tab separated; a file block of "key:<TAB>value" lines, then the channel
    # names over their units; time in seconds from the start of the measurement.
    fs = 600.0
    lines = ["catman Easy/AP ASCII export", "File:\tD:\\Messungen\\Bruecke_0312.BIN", "Comment:\tpassage 3, track 1",
             "Date:\t03.12.2026\tTime: 14:22:05", "Number of channels:\t3", "Sample rate:\t600 Hz", "",
             "Time  1 - default sample rate\tAcc S1 mid\tSG S1 mid", "s\tm/s²\tµm/m"]
    write("hbm-catman.txt", lines, fs, lambda k, t: f"{t:.6f}\t{num(acc(t))}\t{num(strain(t))}")


def dewesoft():
    # DEWESoft export to text: a preamble of "key: value" lines, a blank line, the header with
    # units in brackets; absolute time (date and clock) in the first column; semicolons.
    fs = 1000.0
    lines = ["Dewesoft X3 SP8 - Data export", "Setup: bridge-monitoring.dxs", "Start time: 03.12.2026 14:22:05",
             "Sample rate: 1000 Hz", "", "Date/Time;AI 1/Acc S1 mid [g];AI 2/SG S1 mid [µm/m]"]
    write("dewesoft.txt", lines, fs, lambda k, t: f"03.12.2026 {clock(START + t, 4)};{num(acc(t) / G, True)};{num(strain(t), True)}")


def ni_lvm():
    # NI LabVIEW Measurement file (LVM 2.0): tagged header lines, ***End_of_Header***, a segment
    # header with Delta_X and Y_Unit_Label, then X_Value, the channels and an empty Comment column.
    fs = 500.0
    lines = ["LabVIEW Measurement\t", "Writer_Version\t2", "Reader_Version\t2", "Separator\tTab", "Decimal_Separator\t.",
             "Multi_Headings\tNo", "X_Columns\tOne", "Time_Pref\tRelative", "Operator\tbridge-lab", "Date\t2026/12/03",
             "Time\t14:22:05.0000000000000000", "***End_of_Header***\t", "", "Channels\t2\t\t", f"Samples\t{N}\t{N}\t",
             "Date\t2026/12/03\t2026/12/03\t", "Time\t14:22:05.0000000000000000\t14:22:05.0000000000000000\t",
             "Y_Unit_Label\tm/s^2\tmicrostrain\t", "X_Dimension\tTime\tTime\t", "X0\t0.0000000000000000E+0\t0.0000000000000000E+0\t",
             f"Delta_X\t{1 / fs:.6f}\t{1 / fs:.6f}\t", "***End_of_Header***\t", "X_Value\tAcc S1 mid\tSG S1 mid\tComment"]
    write("ni-labview.lvm", lines, fs, lambda k, t: f"{t:.6f}\t{acc(t):.6f}\t{strain(t):.6f}\t")


def campbell_toa5():
    # Campbell Scientific TOA5: environment line, field names, units, processing, then quoted
    # time stamps with sub-second resolution and a record number.
    fs = 100.0
    lines = ['"TOA5","BridgeS1","CR1000X","12345","CR1000X.Std.04","CPU:bridge.CR1X","51209","Fast"',
             '"TIMESTAMP","RECORD","Acc_S1_mid","SG_S1_mid"', '"TS","RN","g","microstrain"', '"","","Smp","Smp"']
    write("campbell-toa5.dat", lines, fs, lambda k, t: f'"2026-12-03 {clock(START + t, 2)}",{1000 + k},{num(acc(t) / G)},{num(strain(t))}')


def gantner():
    # Gantner test.commander / GI.bench CSV export: a quoted preamble, the date and the clock time
    # in columns of their own, units in a line under the names; semicolons, decimal comma.
    fs = 200.0
    lines = ['"Gantner Instruments GI.bench - CSV export"', '"Project";"Bridge 12 monitoring"', '"Controller";"Q.station 101 SN 0923"',
             '"Sample rate";"200 Hz"', '"Date";"Time";"Acc_S1_mid";"SG_S1_mid"', '"";"";"mg";"µm/m"']
    write("gantner.csv", lines, fs, lambda k, t: f'"03.12.2026";"{clock(START + t, 3)}";{num(1000 * acc(t) / G, True)};{num(strain(t), True)}')


def spreadsheet_de():
    # A spreadsheet saved as CSV in a German locale: semicolons, decimal comma, a "Datum/Zeit"
    # column of serial days (from 1899-12-30) and units in brackets.
    fs = 250.0
    day0 = 46359  # 2026-12-03 as a spreadsheet serial day
    lines = ["Messung Brücke 12;;", "Datum/Zeit;Beschleunigung S1 [m/s²];Dehnung S1 [µm/m]"]
    write("spreadsheet-de.csv", lines, fs, lambda k, t: f"{num(day0 + (START + t) / 86400.0, True, 15)};{num(acc(t), True)};{num(strain(t), True)}")


def issue_preamble():
    # Issue #39's file: "Key: value" lines (a logger with its serial number, a start date and
    # time, the rate), a blank line, a header whose Date/Time column holds date and clock.
    fs = 1250.0
    lines = ["Logger: MX-840B SN 4521", "Start: 03.12.2026 14:22:05", "Start time: 14:22:05", "Sample rate: 1250 Hz", "",
             "Date/Time,Acc S1 mid [m/s^2],SG S1 mid [ue]"]
    write("preamble-datetime.csv", lines, fs, lambda k, t: f"03.12.2026 {clock(START + t, 4)},{num(acc(t))},{num(strain(t))}")


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    for f in (hbm_catman, dewesoft, ni_lvm, campbell_toa5, gantner, spreadsheet_de, issue_preamble):
        f()
