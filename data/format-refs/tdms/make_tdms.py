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
  stopped leaves it).
Every file is then read with npTDMS, and `expected.json` holds, per file and channel, the
values npTDMS reads (RMS, first and last value, count) and the properties satqual uses.

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


def expected():
    out = {}
    for name in ["nptdms_writer.tdms", "nptdms_timestamps.tdms", "handmade_big_endian.tdms"]:
        chans = {}
        for g in TdmsFile.read(D + name).groups():
            for c in g.channels():
                v = c[:]
                entry = {"group": g.name, "count": int(len(v)), "dtype": str(v.dtype)}
                if v.dtype.kind in "fiu":
                    x = v.astype(float)
                    entry.update(rms=float(np.sqrt(np.mean(x * x))), first=float(x[0]), last=float(x[-1]))
                for key in ["wf_increment", "unit_string", "NI_UnitDescription"]:
                    if key in c.properties:
                        entry[key] = c.properties[key]
                chans[c.name] = entry
        out[name] = chans
    with open(D + "expected.json", "w") as f:
        json.dump({"reader": "npTDMS 1.13.0", "files": out}, f, indent=1, sort_keys=True)
        f.write("\n")


write_nptdms()
write_handmade()
expected()
