"""Reference frequencies of the 20-satellite stack by scipy.sparse.linalg.eigsh (ARPACK).

Regenerate (from the repository root):
    python3 - <<'PY' > /tmp/stack-20.toml   # the scene, as tests/modal_sparse.rs builds it
    import re; s = open("test-specs/paper-stack.toml").read()
    s = re.sub(r"(?m)^satellites = .*$", "satellites = 20", s)
    s = re.sub(r"(?m)^bar_length_m = .*$", f"bar_length_m = {3.85 + 14 * 0.55}", s)
    print(s)
    PY
    cargo run --release -- modal /tmp/stack-20.toml --export-matrices /tmp/mx20 --json > /dev/null
    python3 data/modal-refs/stack20_eigsh.py /tmp/mx20 > data/modal-refs/stack20-eigsh.csv
"""
import sys
import numpy as np
import scipy
import scipy.io
import scipy.sparse.linalg as sla

d = sys.argv[1]
K = scipy.io.mmread(f"{d}/KKG.mtx").tocsc()  # K + K_G: the preloaded stiffness the modes use
M = scipy.io.mmread(f"{d}/M.mtx").tocsc()
lmax = (2 * np.pi * 2000.0) ** 2
# Count below 2 kHz from the inertia of K - lmax*M (dense LDL^T; 2120 DOFs).
import scipy.linalg as sl
_, dd, _ = sl.ldl((K - lmax * M).toarray())
ev = np.linalg.eigvalsh(dd)
count = int((ev < 0).sum())
w = sla.eigsh(K, k=count, M=M, sigma=-1.0, which="LM", tol=1e-14, return_eigenvectors=False)
f = np.sort(np.sign(w) * np.sqrt(np.abs(w)) / (2 * np.pi))
print(f"# scipy {scipy.__version__} eigsh(K+K_G, M, sigma=-1, tol=1e-14): the {count} modes below 2000 Hz")
print("mode,frequency_hz")
for i, x in enumerate(f):
    print(f"{i + 1},{x:.17g}")
