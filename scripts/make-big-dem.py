#!/usr/bin/env python3
"""Make a large DEM from the bundled one, deterministically, for the
large-terrain benchmark (scripts/bench-big.sh) and its test-sized run.

    make-big-dem.py FACTOR OUT.vrt

The bundled UTM DEM (344 x 363 pixels of 90 m, nodata -9999) is resampled
FACTOR times finer in each direction (pixel size 90 / FACTOR, the same
origin and extent: FACTOR 29 gives 9,976 x 10,527 = 105 million pixels of
3.10 m), bilinearly between the source pixel centres (clamped at the
edges), plus a fractal detail: value noise on seeded integer lattices of
wavelength 60 m halving down to two output pixels, amplitude proportional
to wavelength^0.8 (1.5 m at 60 m), so the fine terrain is rough at every
scale the coarse DEM cannot show. A pixel is nodata (-9999) where any of
the four source pixels it is interpolated from is nodata, so the holes of
the source stay holes. Written as raw float32 rows (OUT.raw) and a GDAL VRT
(OUT.vrt) that raster2pgsql reads. Rows are made in strips of 256, so the
memory used is a few strips whatever FACTOR is.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.join(HERE, "..", "tests", "data", "jacksboro_fault_dem_utm16n.tif")
NODATA = -9999.0
STRIP = 256


def read_source():
    """The bundled DEM as float32 rows, through gdal_translate (ENVI raw)."""
    with tempfile.TemporaryDirectory() as d:
        raw = os.path.join(d, "src.raw")
        subprocess.run(["gdal_translate", "-q", "-of", "ENVI", "-ot", "Float32", SRC, raw], check=True)
        info = subprocess.run(["gdalinfo", SRC], check=True, capture_output=True, text=True).stdout
        w, h = [int(v) for v in info.split("Size is ")[1].split("\n")[0].split(",")]
        ox, oy = [float(v) for v in info.split("Origin = (")[1].split(")")[0].split(",")]
        px, py = [float(v) for v in info.split("Pixel Size = (")[1].split(")")[0].split(",")]
        a = np.fromfile(raw, dtype="<f4").reshape(h, w)
    return a, (ox, oy, px, py)


def lattice_values(seed, ix, iy):
    """A deterministic value in [-1, 1) for each integer lattice point."""
    h = (ix.astype(np.uint64) * np.uint64(0x9E3779B97F4A7C15)) ^ (
        iy.astype(np.uint64) * np.uint64(0xC2B2AE3D27D4EB4F)) ^ np.uint64(seed * 0x165667B19E3779F9)
    h ^= h >> np.uint64(29)
    h *= np.uint64(0xBF58476D1CE4E5B9)
    h ^= h >> np.uint64(32)
    return (h >> np.uint64(11)).astype(np.float64) / float(1 << 53) * 2.0 - 1.0


def value_noise(seed, x, y):
    """Smoothly interpolated lattice values at (x, y) in lattice units."""
    x0 = np.floor(x)
    y0 = np.floor(y)
    fx = x - x0
    fy = y - y0
    sx = fx * fx * (3 - 2 * fx)
    sy = fy * fy * (3 - 2 * fy)
    ix = x0.astype(np.int64) + (1 << 20)
    iy = y0.astype(np.int64) + (1 << 20)
    v00 = lattice_values(seed, ix, iy)
    v10 = lattice_values(seed, ix + 1, iy)
    v01 = lattice_values(seed, ix, iy + 1)
    v11 = lattice_values(seed, ix + 1, iy + 1)
    return (v00 * (1 - sx) + v10 * sx) * (1 - sy) + (v01 * (1 - sx) + v11 * sx) * sy


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    k = int(sys.argv[1])
    out = sys.argv[2]
    if k < 1 or not out.endswith(".vrt"):
        sys.exit("FACTOR must be a positive integer and OUT end in .vrt")
    src, (ox, oy, px, py) = read_source()
    sh, sw = src.shape
    w, h = sw * k, sh * k
    opx, opy = px / k, py / k
    bad = src == NODATA
    octaves = []
    wl = 60.0
    while wl >= 2 * abs(opx):
        octaves.append((wl, 1.5 * (wl / 60.0) ** 0.8))
        wl /= 2
    raw = out[:-4] + ".raw"
    # source-pixel coordinates of the output pixel centres, clamped
    sxf = np.clip((np.arange(w) + 0.5) / k - 0.5, 0, sw - 1)
    c0 = np.minimum(np.floor(sxf).astype(np.int64), sw - 2)
    tx = sxf - c0
    wx = ox + (np.arange(w) + 0.5) * opx  # world x of the centres
    with open(raw, "wb") as f:
        for r0 in range(0, h, STRIP):
            rows = np.arange(r0, min(h, r0 + STRIP))
            syf = np.clip((rows + 0.5) / k - 0.5, 0, sh - 1)
            q0 = np.minimum(np.floor(syf).astype(np.int64), sh - 2)
            ty = (syf - q0)[:, None]
            a = src[q0][:, c0]
            b = src[q0][:, c0 + 1]
            c = src[q0 + 1][:, c0]
            d = src[q0 + 1][:, c0 + 1]
            z = (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty
            wy = (oy + (rows + 0.5) * opy)[:, None]
            for i, (wl, amp) in enumerate(octaves):
                z = z + amp * value_noise(i + 1, wx[None, :] / wl, wy / wl)
            hole = bad[q0][:, c0] | bad[q0][:, c0 + 1] | bad[q0 + 1][:, c0] | bad[q0 + 1][:, c0 + 1]
            z = np.where(hole, NODATA, z).astype("<f4")
            z.tofile(f)
    with open(out, "w") as f:
        f.write(f"""<VRTDataset rasterXSize="{w}" rasterYSize="{h}">
  <SRS>EPSG:32616</SRS>
  <GeoTransform>{ox!r}, {opx!r}, 0.0, {oy!r}, 0.0, {opy!r}</GeoTransform>
  <VRTRasterBand dataType="Float32" band="1" subClass="VRTRawRasterBand">
    <NoDataValue>{NODATA}</NoDataValue>
    <SourceFilename relativeToVRT="1">{os.path.basename(raw)}</SourceFilename>
    <ByteOrder>LSB</ByteOrder>
    <ImageOffset>0</ImageOffset>
    <PixelOffset>4</PixelOffset>
    <LineOffset>{4 * w}</LineOffset>
  </VRTRasterBand>
</VRTDataset>
""")
    print(f"{w} x {h} = {w * h} pixels of {opx!r} m, {int(np.count_nonzero(bad))} nodata source pixels, {len(octaves)} octaves of detail")


if __name__ == "__main__":
    main()
