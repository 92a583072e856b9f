"""TDMS files for tests/signal_formats.rs, and what an independent reader (npTDMS) reads in them.

Two writers, so that satqual is not checked against its own reading of the format:
- npTDMS's TdmsWriter (little-endian, contiguous data, a new object list in every segment):
  `nptdms_writer.tdms` (three segments of a shaker-run group: f64, f32 and i16 channels with
  `unit_string` and `wf_increment`, plus a string channel and a temperature at 2 Hz) and `nptdms_timestamps.tdms` (a
  channel of timestamps at 1 kHz beside an acceleration with no `wf_increment`).
- The segment builder below, written from NI's "TDMS File Format Internal Structure", for what
  TdmsWriter never writes: `handmade_big_endian.tdms` (big-endian; interleaved raw data; a
  segment with no metadata that reuses the object list; a segment whose objects say "same raw
  data index as before"; a last segment whose length field is all ones, as a writer that
  stopped leaves it); `handmade_daqmx.tdms` (NI-DAQmx logging's layout: two acquisition
  buffers of interleaved i16 rows, format-changing scalers, a DAQmx raw → polynomial → linear
  scaling chain in the channel properties, and a segment with no metadata); and
  `handmade_scaled_i16.tdms` (a plain i16 channel with a linear scaling in its properties, as
  LabVIEW's raw writes leave it).
Every file is then read with npTDMS, and `expected.json` holds, per file and channel, the
values npTDMS reads (RMS, first and last value, count; scaled where the file states a scaling)
and the properties satqual uses. First and last values are written as text (Python's repr),
which a correctly rounding parser reads back to the same bits.

Run from the repository root:  python3 data/format-refs/tdms/make_tdms.py
Versions used: numpy 2.4.6, npTDMS 1.13.0.
"""
import json
import struct
import numpy as np
from nptdms import TdmsFile, TdmsWriter, RootObject, GroupObject, ChannelObject

D = "data/format-refs/tdms/"
FS = 2048.0


def shaker_signals(n, start):
    """Two tones and seeded noise: a control acceleration (g), a response (m/s²), a force (N)."""
    rng = np.random.default_rng(7 + start)
    t = (start + np.arange(n)) / FS
    ctrl = 1.5 * np.sin(2 * np.pi * 80 * t) + 0.3 * rng.standard_normal(n)
    resp = 9.80665 * (4.0 * np.sin(2 * np.pi * 80 * t + 0.4) + 0.5 * rng.standard_normal(n))
    force = np.round(800 * np.sin(2 * np.pi * 80 * t + 0.1)).astype(np.int16)
    return ctrl, resp.astype(np.float32), force


def write_nptdms():
    props = {"wf_increment": 1.0 / FS, "wf_start_offset": 0.0}
    with TdmsWriter(D + "nptdms_writer.tdms") as w:
        for k, n in enumerate([4096, 4096, 2048]):
            ctrl, resp, force = shaker_signals(n, 4096 * k)
            objs = [
                ChannelObject("Shaker run", "Acc ctrl", ctrl, dict(props, unit_string="g")),
                ChannelObject("Shaker run", "Acc resp", resp, dict(props, unit_string="m/s^2")),
                ChannelObject("Shaker run", "Force", force, dict(props, unit_string="N")),
            ]
            if k == 0:
                objs = [RootObject({"operator": "npTDMS"}), GroupObject("Shaker run", {})] + objs
                objs.append(ChannelObject("Notes", "Comment", np.array(["run 1", "ok"])))
                # A slow channel logged beside the fast ones, as LabVIEW loggers do.
                objs.append(ChannelObject("Notes", "Temperature", 21.0 + 0.01 * np.arange(20),
                                          {"wf_increment": 0.5, "unit_string": "degC"}))
            w.write_segment(objs)
    t0 = np.datetime64("2026-11-27T10:00:00", "us")
    times = t0 + np.arange(1000) * np.timedelta64(1000, "us")
    acc = np.sin(2 * np.pi * 50 * np.arange(1000) / 1000.0)
    with TdmsWriter(D + "nptdms_timestamps.tdms") as w:
        w.write_segment([
            ChannelObject("Log", "Time", times),
            ChannelObject("Log", "acc", acc, {"unit_string": "g"}),
        ])


def s(text, e):
    b = text.encode()
    return struct.pack(e + "I", len(b)) + b


def prop(name, value, e):
    if isinstance(value, str):
        return s(name, e) + struct.pack(e + "I", 0x20) + s(value, e)
    if isinstance(value, int):  # NI writes scale counts and input sources as u32
        return s(name, e) + struct.pack(e + "I", 7) + struct.pack(e + "I", value)
    return s(name, e) + struct.pack(e + "I", 10) + struct.pack(e + "d", value)


def obj(path, e, index=None, props=()):
    """An object's metadata: index None = no data (0xFFFFFFFF), "same" = as before (0)."""
    if index is None:
        b = s(path, e) + struct.pack(e + "I", 0xFFFFFFFF)
    elif index == "same":
        b = s(path, e) + struct.pack(e + "I", 0)
    else:
        code, count = index
        b = s(path, e) + struct.pack(e + "IIIQ", 20, code, 1, count)
    b += struct.pack(e + "I", len(props))
    for name, value in props:
        b += prop(name, value, e)
    return b


META, NEW_LIST, RAW, INTERLEAVED, BIG = 1 << 1, 1 << 2, 1 << 3, 1 << 5, 1 << 6


def segment(toc, objects, raw, e, unfinished=False):
    meta = struct.pack(e + "I", len(objects)) + b"".join(objects) if toc & META else b""
    nxt = 0xFFFFFFFFFFFFFFFF if unfinished else len(meta) + len(raw)
    return b"TDSm" + struct.pack("<I", toc) + struct.pack(e + "IQQ", 4713, nxt, len(meta)) + meta + raw


def write_handmade():
    e = ">"
    n = 100
    a = np.sin(2 * np.pi * 10 * np.arange(500) / 1000.0) * 2.5
    b = (np.arange(500) * 37 % 2001 - 1000).astype(np.int32)
    dt = [("wf_increment", 0.001)]
    first = [
        obj("/", e, props=[("name", "handmade")]),
        obj("/'Rig'", e),
        obj("/'Rig'/'acc ''x'''", e, (10, n), dt + [("unit_string", "g")]),
        obj("/'Rig'/'load'", e, (3, n), dt + [("NI_UnitDescription", "N")]),
    ]

    def rows(lo, hi):  # interleaved: a[k], b[k], a[k+1], ...
        return b"".join(struct.pack(">di", a[k], b[k]) for k in range(lo, hi))

    def blocks(lo, hi):  # contiguous: every a, then every b
        return a[lo:hi].astype(">f8").tobytes() + b[lo:hi].astype(">i4").tobytes()

    data = segment(META | NEW_LIST | RAW | INTERLEAVED | BIG, first, rows(0, 100) + rows(100, 200), e)
    data += segment(RAW | INTERLEAVED | BIG, [], rows(200, 300), e)
    same = [obj("/'Rig'/'acc ''x'''", e, "same"), obj("/'Rig'/'load'", e, "same")]
    data += segment(META | RAW | BIG, same, blocks(300, 400), e)
    data += segment(RAW | BIG, [], blocks(400, 500), e, unfinished=True)
    with open(D + "handmade_big_endian.tdms", "wb") as f:
        f.write(data)


def daqmx_obj(path, count, scalers, widths, props):
    """A DAQmx channel: raw data index 0x1269, data type 0xFFFFFFFF, then its scalers
    (DAQmx type, buffer, byte offset, format bitmap, scale id) and the buffer widths."""
    e = "<"
    b = s(path, e) + struct.pack(e + "IIIQ", 0x1269, 0xFFFFFFFF, 1, count)
    b += struct.pack(e + "I", len(scalers))
    for (dtype, buf, offset, scale_id) in scalers:
        b += struct.pack(e + "IIIII", dtype, buf, offset, 0, scale_id)
    b += struct.pack(e + "I", len(widths)) + b"".join(struct.pack(e + "I", w) for w in widths)
    b += struct.pack(e + "I", len(props)) + b"".join(prop(n, v, e) for n, v in props)
    return b


def iepe_chain(coefficients, sensitivity_v_per_unit, unit):
    """DAQmx's chain for an IEPE sensor: raw counts (scale 0, the DAQmx scaler) → volts
    (polynomial, scale 1) → physical unit (linear, scale 2)."""
    p = [("NI_Scaling_Status", "unscaled"), ("NI_Number_Of_Scales", 3),
         ("NI_Scale[1]_Scale_Type", "Polynomial"),
         ("NI_Scale[1]_Polynomial_Coefficients_Size", len(coefficients)),
         ("NI_Scale[1]_Polynomial_Input_Source", 0)]
    p += [("NI_Scale[1]_Polynomial_Coefficients[%d]" % k, c) for k, c in enumerate(coefficients)]
    p += [("NI_Scale[2]_Scale_Type", "Linear"),
          ("NI_Scale[2]_Linear_Slope", 1.0 / sensitivity_v_per_unit),
          ("NI_Scale[2]_Linear_Y_Intercept", 0.0),
          ("NI_Scale[2]_Linear_Input_Source", 1),
          ("NI_UnitDescription", unit), ("wf_increment", 1.0 / 25600)]
    return p


def write_daqmx():
    e = "<"
    n = 512
    rng = np.random.default_rng(11)
    counts = [np.clip(np.round(12000 * np.sin(2 * np.pi * 440 * np.arange(3 * n) / 25600)
                               + 300 * rng.standard_normal(3 * n)), -32768, 32767).astype("<i2")
              for _ in range(3)]
    poly = [2.1e-4, 3.0518e-4, 1.2e-12, -4.0e-17]
    chans = [
        daqmx_obj("/'DAQ'/'ai0'", n, [(3, 0, 0, 0)], [4, 2], iepe_chain(poly, 0.1, "g")),
        daqmx_obj("/'DAQ'/'ai1'", n, [(3, 0, 2, 0)], [4, 2], iepe_chain(poly, 0.0225, "N")),
        daqmx_obj("/'DAQ'/'ai2'", n, [(3, 1, 0, 0)], [4, 2], iepe_chain(poly, 0.05, "g")),
    ]
    meta_objs = [obj("/", e), obj("/'DAQ'", e)] + chans

    def chunk(k):  # buffer 0: rows of (ai0, ai1); buffer 1: rows of ai2
        lo, hi = k * n, (k + 1) * n
        rows0 = np.empty(2 * n, dtype="<i2")
        rows0[0::2], rows0[1::2] = counts[0][lo:hi], counts[1][lo:hi]
        return rows0.tobytes() + counts[2][lo:hi].tobytes()

    DAQMX = 1 << 7
    data = segment(META | NEW_LIST | RAW | DAQMX, meta_objs, chunk(0) + chunk(1), e)
    data += segment(RAW | DAQMX, [], chunk(2), e)
    with open(D + "handmade_daqmx.tdms", "wb") as f:
        f.write(data)


def write_scaled_i16():
    e = "<"
    x = (np.arange(800) * 97 % 4001 - 2000).astype("<i2")
    props = [("NI_Scaling_Status", "unscaled"), ("NI_Number_Of_Scales", 1),
             ("NI_Scale[0]_Scale_Type", "Linear"), ("NI_Scale[0]_Linear_Slope", 0.0025),
             ("NI_Scale[0]_Linear_Y_Intercept", 0.125),
             ("NI_Scale[0]_Linear_Input_Source", 0xFFFFFFFF),
             ("unit_string", "g"), ("wf_increment", 1.0 / 4096)]
    objs = [obj("/", e), obj("/'Raw'", e), obj("/'Raw'/'acc'", e, (2, len(x)), props)]
    with open(D + "handmade_scaled_i16.tdms", "wb") as f:
        f.write(segment(META | NEW_LIST | RAW, objs, x.tobytes(), e))


def expected():
    out = {}
    for name in ["nptdms_writer.tdms", "nptdms_timestamps.tdms", "handmade_big_endian.tdms",
                 "handmade_daqmx.tdms", "handmade_scaled_i16.tdms"]:
        chans = {}
        for g in TdmsFile.read(D + name).groups():
            for c in g.channels():
                v = c[:]
                entry = {"group": g.name, "count": int(len(v)), "dtype": str(v.dtype)}
                if v.dtype.kind in "fiu":
                    x = v.astype(float)
                    entry.update(rms=float(np.sqrt(np.mean(x * x))), first=repr(float(x[0])),
                                 last=repr(float(x[-1])))
                for key in ["wf_increment", "unit_string", "NI_UnitDescription"]:
                    if key in c.properties:
                        entry[key] = c.properties[key]
                chans[c.name] = entry
        out[name] = chans
    with open(D + "expected.json", "w") as f:
        json.dump({"reader": "npTDMS 1.13.0", "files": out}, f, indent=1, sort_keys=True)
        f.write("\n")


def nptdms_test_files():
    """npTDMS ships four TDMS files written by LabVIEW and NI-DAQmx in its test folder (raw1:
    DAQmx data with linear scales; big_endian: a LabVIEW example; Digital_Input: SignalExpress,
    three rates in nine segments; raw_timestamps). They are LGPL-3.0 and stay in the installed
    package: `nptdms_testdata.json` holds npTDMS's reading of them and their sizes, and the
    test reads them where npTDMS is installed (pip install npTDMS==1.13.0)."""
    import os
    import nptdms
    folder = os.path.join(os.path.dirname(nptdms.__file__), "test", "data")
    out = {}
    for name in ["raw1.tdms", "big_endian.tdms", "Digital_Input.tdms", "raw_timestamps.tdms"]:
        path = os.path.join(folder, name)
        f = TdmsFile.read(path)
        channels = [(g.name, c) for g in f.groups() for c in g.channels()]
        chans = {}
        for group, c in channels:
            shared = sum(1 for _, d in channels if d.name == c.name) > 1
            v = c[:].astype(float)
            chans[group + "/" + c.name if shared else c.name] = {
                "count": int(len(v)), "first": repr(float(v[0])), "last": repr(float(v[-1])),
                "rms": float(np.sqrt(np.mean(v * v))),
                "wf_increment": c.properties.get("wf_increment")}
        out[name] = {"bytes": os.path.getsize(path), "channels": chans}
    with open(D + "nptdms_testdata.json", "w") as fh:
        json.dump({"reader": "npTDMS 1.13.0", "folder": "nptdms/test/data", "files": out},
                  fh, indent=1, sort_keys=True)
        fh.write("\n")


write_nptdms()
write_handmade()
write_daqmx()
write_scaled_i16()
expected()
nptdms_test_files()
