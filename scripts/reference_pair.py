"""Two independent renders of a scene as one reference, and that reference's own error.

    reference_pair.py A B OUT

writes OUT = (A + B) / 2 (any format Mitsuba's Bitmap writes, by OUT's extension) and prints
the estimated relMSE of OUT against the converged image:

    relMSE(OUT) ~ relMSE(A, B) / 4,

since A - B has twice the variance of either and OUT half of it (A and B unbiased, independent
and equally converged; relMSE with OUT's b^2 + 0.01 as the denominator, as `ppm compare` and
scripts/smallvcm_stats.py use). Measured against OUT, an image's relMSE is its own plus this
figure on average: subtracting it leaves the image's own error, so ratios of errors measured
against OUT are not pulled toward 1 by the reference's noise. Run with Mitsuba's python
(/work/venv-mitsuba/bin/python; it reads EXR and HDR).
"""

import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def read(path):
    """The image's R, G, B channels as linear floats (ppm's EXR has more channels)."""
    bitmap = mi.Bitmap(path)
    names = [field.name for field in bitmap.struct_()]
    data = np.array(bitmap, dtype=np.float64)
    if bitmap.channel_count() == 3:
        return data
    return data[:, :, [names.index(c) for c in ("R", "G", "B")]]


def main():
    a, b = read(sys.argv[1]), read(sys.argv[2])
    out = 0.5 * (a + b)
    noise = np.mean((a - b) ** 2 / (out**2 + 0.01)) / 4.0
    mi.Bitmap(out.astype(np.float32)).write(sys.argv[3])
    print(f"{noise:.4g}")


if __name__ == "__main__":
    main()
