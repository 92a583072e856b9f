"""WAV files for tests/signal_wav.rs, and what an independent reader (scipy.io.wavfile) reads
in them.

Two writers: Python's `wave` module (PCM of 1, 2, 3 and 4 bytes; 24-bit is the depth of most
recorders) and scipy.io.wavfile.write (IEEE floats, and WAVE_FORMAT_EXTENSIBLE where scipy uses
it). `expected.json` holds, per file and channel, scipy's reading as a fraction of full scale
(integers ÷ 2^(bits−1); 8-bit offset by 128), the rate, the count, the RMS, and the first and
last values as text (Python's repr, read back to the same bits).

Run from the repository root:  python3 data/format-refs/wav/make_wav.py
Versions used: numpy 2.4.6, scipy 1.17.1.
"""
import json
import wave
import numpy as np
from scipy.io import wavfile

D = "data/format-refs/wav/"


def signals(n, channels, fs, seed):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    return np.stack([0.6 * np.sin(2 * np.pi * (120 + 40 * c) * t) + 0.05 * rng.standard_normal(n)
                     for c in range(channels)], axis=1)


def write_pcm(name, width, channels, fs, n):
    x = signals(n, channels, fs, width)
    full = 2 ** (8 * width - 1)
    ints = np.clip(np.round(x * full), -full, full - 1).astype(np.int64)
    if width == 1:
        raw = (ints + 128).astype(np.uint8).tobytes()
    else:
        raw = b"".join(int(v).to_bytes(width, "little", signed=True) for v in ints.ravel())
    with wave.open(D + name, "wb") as w:
        w.setnchannels(channels)
        w.setsampwidth(width)
        w.setframerate(fs)
        w.writeframes(raw)


def write_float(name, dtype, channels, fs, n):
    wavfile.write(D + name, fs, signals(n, channels, fs, 40).astype(dtype))


def expected():
    out = {}
    for name in FILES:
        fs, x = wavfile.read(D + name)
        if x.ndim == 1:
            x = x[:, None]
        if x.dtype == np.uint8:
            v = (x.astype(float) - 128.0) / 128.0
        elif x.dtype.kind == "i":
            # scipy returns 24-bit samples in the top three bytes of an int32.
            v = x.astype(float) / 2.0 ** (8 * x.dtype.itemsize - 1)
        else:
            v = x.astype(float)
        out[name] = {"fs_hz": fs, "channels": {
            "ch%d" % (c + 1): {"count": int(len(v)), "first": repr(float(v[0, c])),
                               "last": repr(float(v[-1, c])),
                               "rms": float(np.sqrt(np.mean(v[:, c] ** 2)))}
            for c in range(v.shape[1])}}
    with open(D + "expected.json", "w") as f:
        json.dump({"reader": "scipy.io.wavfile 1.17.1", "files": out}, f, indent=1, sort_keys=True)
        f.write("\n")


FILES = ["wave_pcm8_1ch.wav", "wave_pcm16_2ch.wav", "wave_pcm24_2ch.wav", "wave_pcm32_1ch.wav",
         "scipy_float32_3ch.wav", "scipy_float64_1ch.wav"]
write_pcm(FILES[0], 1, 1, 8000, 1000)
write_pcm(FILES[1], 2, 2, 8000, 2000)
write_pcm(FILES[2], 3, 2, 48000, 4800)
write_pcm(FILES[3], 4, 1, 8000, 1000)
write_float(FILES[4], np.float32, 3, 25600, 2560)
write_float(FILES[5], np.float64, 1, 2048, 2048)
expected()
