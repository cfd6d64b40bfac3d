#!/usr/bin/env python3
"""Writes the three equirectangular environment maps shipped in
assets/hdri/ (CC0: made here, from nothing but these formulas).

- studio_softboxes.hdr: a dark studio with a large key softbox 45° to the
  right, a strip light behind on the left and a warm floor bounce;
- overcast_sky.hdr: a CIE overcast sky (luminance ∝ (1 + 2 sin h)/3, Moon
  & Spencer 1942, the CIE standard overcast sky) over grey ground;
- golden_hour.hdr: a low sun 8° up with a warm horizon glow and a blue
  zenith.

Layout: environment.rs's: row 0 looks up, the centre column looks down
−z, u grows with the azimuth atan2(x, −z). Radiance RGBE (Ward 1991),
flat (no run-length encoding), 512 × 256.

Run: .venv/bin/python tools/make_hdri.py
"""
import math
import os

import numpy as np

W, H = 512, 256
OUT = os.path.join(os.path.dirname(__file__), "..", "assets", "hdri")


def directions():
    u = (np.arange(W) + 0.5) / W
    v = (np.arange(H) + 0.5) / H
    phi = (u - 0.5) * 2 * math.pi
    theta = v * math.pi
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    x = np.sin(th) * np.sin(ph)
    y = np.cos(th)
    z = -np.sin(th) * np.cos(ph)
    return x, y, z


def soft_rect(x, y, z, centre_az, centre_el, half_w, half_h, radiance):
    """A rectangular light seen in direction (az, el) with soft edges."""
    az = np.degrees(np.arctan2(x, -z))
    el = np.degrees(np.arcsin(np.clip(y, -1, 1)))
    daz = (az - centre_az + 180) % 360 - 180
    fall = lambda d, h: np.clip((h - np.abs(d)) / 3.0 + 0.5, 0, 1)
    m = fall(daz, half_w) * fall(el - centre_el, half_h)
    return m[..., None] * np.array(radiance)[None, None, :]


def studio():
    x, y, z = directions()
    img = np.zeros((H, W, 3))
    img += np.array([0.02, 0.021, 0.024])
    img += np.where(y[..., None] < 0, np.array([0.05, 0.04, 0.03]) * (-y[..., None]), 0)
    img += soft_rect(x, y, z, 45, 20, 25, 18, [9.0, 8.8, 8.4])
    img += soft_rect(x, y, z, -150, 10, 8, 30, [3.0, 3.1, 3.3])
    img += soft_rect(x, y, z, -60, 35, 15, 10, [0.8, 0.85, 0.9])
    return img


def overcast():
    x, y, z = directions()
    sky = 1.2 * (1 + 2 * np.clip(y, 0, 1)) / 3
    img = np.where(
        y[..., None] >= 0,
        sky[..., None] * np.array([0.95, 0.98, 1.05]),
        np.array([0.12, 0.12, 0.11]),
    )
    return img


def golden_hour():
    x, y, z = directions()
    sun = np.array([math.sin(math.radians(120)) * math.cos(math.radians(8)),
                    math.sin(math.radians(8)),
                    -math.cos(math.radians(120)) * math.cos(math.radians(8))])
    cosang = x * sun[0] + y * sun[1] + z * sun[2]
    ang = np.degrees(np.arccos(np.clip(cosang, -1, 1)))
    h = np.clip(y, 0, 1)
    sky = (np.array([0.25, 0.4, 0.8])[None, None, :] * h[..., None] ** 0.5
           + np.array([1.2, 0.6, 0.25])[None, None, :] * np.exp(-h / 0.08)[..., None])
    glow = np.exp(-ang / 12.0)[..., None] * np.array([3.0, 1.6, 0.6])
    disc = (ang < 1.5)[..., None] * np.array([4000.0, 2600.0, 1300.0])
    ground = np.array([0.10, 0.07, 0.045])
    img = np.where(y[..., None] >= 0, sky + glow + disc, ground + 0.3 * glow)
    return img


def write_rgbe(path, img):
    rgb = np.maximum(img, 0).astype(np.float64)
    m = rgb.max(axis=2)
    e = np.where(m > 1e-32, np.floor(np.log2(np.maximum(m, 1e-32))) + 1, 0)
    scale = np.where(m > 1e-32, 256.0 / np.exp2(e), 0)
    mant = np.clip(np.floor(rgb * scale[..., None]), 0, 255).astype(np.uint8)
    exp = np.where(m > 1e-32, e + 128, 0).astype(np.uint8)
    data = np.concatenate([mant, exp[..., None]], axis=2)
    head = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {H} +X {W}\n".encode()
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(head)
        f.write(data.tobytes())
    os.replace(tmp, path)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    for name, fn in [("studio_softboxes", studio), ("overcast_sky", overcast),
                     ("golden_hour", golden_hour)]:
        write_rgbe(os.path.join(OUT, name + ".hdr"), fn())
        print("wrote", name)
