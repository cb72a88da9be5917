#!/usr/bin/env python3
"""Writes a copy of a KITTI .bin cloud with every point shifted by (DX, 0, 0) metres: a
well-conditioned registration moves by about DX; a path-sensitive one by much more.
usage: perturb_bin.py IN.bin OUT.bin DX"""
import struct
import sys

data = open(sys.argv[1], "rb").read()
dx = float(sys.argv[3])
out = bytearray()
for x, y, z, i in struct.iter_unpack("<4f", data):
    out += struct.pack("<4f", x + dx, y, z, i)
open(sys.argv[2], "wb").write(out)
