"""Error statistics of repeated renders for scripts/smallvcm_compare.sh.

Reads images with Mitsuba's Bitmap (OpenEXR from ppm, Radiance .hdr from SmallVCM), so run it
with the Mitsuba venv's python (/work/venv-mitsuba/bin/python; numpy comes with it).

    smallvcm_stats.py REFERENCE IMAGE [IMAGE ...]

prints one line, tab-separated: the number of images K, the reference's mean (RGB average), the
images' mean, the mean over the images of relMSE against REFERENCE, its standard error, and the
relative variance across the images:

    relMSE = 1/(3P) sum_{pixels, channels} (a - b)^2 / (b^2 + 0.01)     (ppm compare's, b = REFERENCE)
    relVar = 1/(3P) sum_{pixels, channels} s^2 / (b^2 + 0.01),

s^2 the unbiased sample variance of the K images at the pixel. relVar is the variance part of
one image's relMSE, free of the reference's own noise and of any difference between the
reference and what the images converge to (so it compares the variance of renderers or
techniques whose images converge to different things, such as light tracing's).
"""

import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def read(path):
    """The image's R, G, B channels as linear floats (ppm's EXR has more channels)."""
    bitmap = mi.Bitmap(path)
    if bitmap.channel_count() == 3:
        bitmap = bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
        return np.array(bitmap, dtype=np.float64)
    names = [field.name for field in bitmap.struct_()]
    data = np.array(bitmap, dtype=np.float64)
    return data[:, :, [names.index(c) for c in ("R", "G", "B")]]


def main():
    reference = read(sys.argv[1])
    images = np.stack([read(p) for p in sys.argv[2:]])
    k = len(images)
    denominator = reference**2 + 0.01
    relmse = ((images - reference) ** 2 / denominator).mean(axis=(1, 2, 3))
    stderr = relmse.std(ddof=1) / np.sqrt(k) if k > 1 else float("nan")
    relvar = (images.var(axis=0, ddof=1) / denominator).mean() if k > 1 else float("nan")
    print(
        f"{k}\t{reference.mean():.5f}\t{images.mean():.5f}\t{relmse.mean():.4g}\t{stderr:.4g}"
        f"\t{relvar:.4g}"
    )


if __name__ == "__main__":
    main()
