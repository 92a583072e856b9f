"""References for the log-format corpus test (tests/signal_formats.rs).

For every third-party log in data/realdata/ that satqual reads, one number per file (the RMS of
one channel, in the file's own unit, over every sample) computed with an independent reader:
pyuff (UFF58 / 58b), lvm_read (LabVIEW .lvm), scipy.io.loadmat (MAT), numpy.loadtxt (CSV).
Also writes the synthetic lab-style MAT-files of data/format-refs/ (scipy.io.savemat), whose
expected values are analytic.

Run from the repository root:  python3 data/format-refs/make_corpus_refs.py
Versions used: numpy 2.4.6, scipy 1.17.1, pyuff 2.5.8, lvm_read 1.26.
"""
import json
import numpy as np
import scipy.io as sio
import pyuff
import lvm_read

R = "data/realdata/"
refs = []


def add(path, channel, values, reader, fs=None):
    v = np.asarray(values, dtype=float)
    refs.append({
        "file": path,
        "channel": channel,
        "reader": reader,
        "samples": int(v.size),
        "rms": float(np.sqrt(np.mean(v * v))),
        "fs_hz": fs,
    })


# UFF58 binary (58b) and ASCII.
u = pyuff.UFF(R + "dialects/pyuff/Sample_UFF58b_bin.uff").read_sets(0)
add("dialects/pyuff/Sample_UFF58b_bin.uff", "Mic 01", u["data"], "pyuff 2.5.8",
    1.0 / u["abscissa_inc"])
u = pyuff.UFF(R + "pyuff-vibcontrol-psd/sample_dataset58_psd.uff").read_sets(0)
add("pyuff-vibcontrol-psd/sample_dataset58_psd.uff", "Channel 1", np.real(u["data"]), "pyuff 2.5.8")

# LabVIEW .lvm: column index in lvm_read's data array for the named channel.
lvm = [
    ("short.lvm", "Excitation (Trigger)", 0, 25600.0),
    ("short.lvm", "Response (Trigger)", 1, 25600.0),
    ("multi_time_column.lvm", "Acceleration", 3, 51200.0),
    ("no_decimal_separator.lvm", "az", 5, 4000.0),
    ("with_empty_fields.lvm", "Dev0/Ai2", 2, 1000.0),
    ("with_comments.lvm", "Volume (ml)", 3, None),
    ("uneven_comments.lvm", "TC06 Diffuser", 1, 2.0),
    ("short_new_line_end.lvm", "Response (Trigger)", 1, 25600.0),
]
for name, ch, col, fs in lvm:
    seg = lvm_read.read(R + "dialects/lvm_read/" + name, read_from_pickle=False, dump_file=False)[0]
    add("dialects/lvm_read/" + name, ch, seg["data"][:, col], "lvm_read 1.26", fs)

# MATLAB MAT-files written by MATLAB.
m = sio.loadmat(R + "scipy-matlab/testdouble_7.4_GLNX86.mat")
add("scipy-matlab/testdouble_7.4_GLNX86.mat", "testdouble", m["testdouble"].ravel(), "scipy.io.loadmat 1.17.1")
m = sio.loadmat(R + "scipy-matlab/testmatrix_6.5.1_GLNX86.mat")
add("scipy-matlab/testmatrix_6.5.1_GLNX86.mat", "testmatrix(3,:)", m["testmatrix"][2, :], "scipy.io.loadmat 1.17.1")
m = sio.loadmat(R + "scipy-matlab/big_endian.mat")
add("scipy-matlab/big_endian.mat", "floats(:,2)", m["floats"][:, 1], "scipy.io.loadmat 1.17.1")
m = sio.loadmat(R + "scipy-matlab/teststruct_7.4_GLNX86.mat")
add("scipy-matlab/teststruct_7.4_GLNX86.mat", "teststruct.doublefield",
    m["teststruct"]["doublefield"][0, 0].ravel(), "scipy.io.loadmat 1.17.1")

# CSV conversions of third-party records.
csv = [
    ("usc-shaker-beam/data_set_1_3200Hz.csv", "acceleration_g", 3),
    ("hrshm-pcb-shock/acc_base_a0_first5ms.csv", "base_accel_g", 1),
] + [("pyfrf-impact/impact_%d.csv" % k, "acceleration", 2) for k in range(1, 6)]
for path, ch, col in csv:
    add(path, ch, np.loadtxt(R + path, delimiter=",", skiprows=1)[:, col], "numpy.loadtxt 2.4.6")

with open("data/format-refs/corpus_refs.json", "w") as f:
    json.dump({"generated_by": "data/format-refs/make_corpus_refs.py", "refs": refs}, f, indent=1)

# Synthetic lab-style MAT-files: a struct of vectors with a time vector, and top-level vectors
# with a scalar rate. 2048 Hz, 1 s; a 2 g, 100 Hz sine has an RMS of 2/sqrt(2) g exactly over
# whole periods.
fs = 2048.0
t = np.arange(2048) / fs
acc = 2.0 * np.sin(2 * np.pi * 100.0 * t)
force = 5.0 * np.cos(2 * np.pi * 50.0 * t)
sio.savemat("data/format-refs/lab_struct_v7.mat",
            {"run": {"t": t, "accel_g": acc, "force_N": force, "operator": "lab"}},
            do_compression=True)
sio.savemat("data/format-refs/lab_vectors_v6.mat",
            {"fs": fs, "accel_g": acc.reshape(-1, 1), "force_N": force.reshape(1, -1)},
            do_compression=False)
print(len(refs), "references")
