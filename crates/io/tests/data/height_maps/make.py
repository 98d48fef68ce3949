#!/usr/bin/env python3
"""Writes the X3P and SDF files of this directory with the Python standard library
alone (zipfile, hashlib, struct), independently of the Rust writers, so that the
readers are tested on files they did not write. Run it from anywhere; it rewrites the
files beside it. The heights are given by formulas that tests/height_maps.rs repeats.
"""

import hashlib
import os
import struct
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))


def md5(data):
    return hashlib.md5(data).hexdigest()


def main_xml(nx, ny, dx, dy, z_type, data_part, z_extra=""):
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
 <Record1>
  <Revision>ISO5436 - 2000</Revision>
  <FeatureType>SUR</FeatureType>
  <Axes>
   <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>{dx!r}</Increment><Offset>0.0</Offset></CX>
   <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>{dy!r}</Increment><Offset>0.0</Offset></CY>
   <CZ><AxisType>A</AxisType><DataType>{z_type}</DataType>{z_extra}</CZ>
  </Axes>
 </Record1>
 <Record2>
  <Date>2024-01-01T00:00:00+00:00</Date>
  <Creator>make.py</Creator>
  <Instrument><Manufacturer>none</Manufacturer><Model>none</Model><Serial>0</Serial><Version>0</Version></Instrument>
  <CalibrationDate>2024-01-01T00:00:00+00:00</CalibrationDate>
  <ProbingSystem><Type>NonContacting</Type><Identification>none</Identification></ProbingSystem>
  <Comment>test data</Comment>
 </Record2>
 <Record3>
  <MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
{data_part}
 </Record3>
 <Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>
</p:ISO5436_2>
""".encode("utf-8")


def write_x3p(name, xml, entries):
    with zipfile.ZipFile(os.path.join(HERE, name), "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("main.xml", xml)
        for entry, data in entries:
            archive.writestr(entry, data)
        archive.writestr("md5checksum.hex", f"{md5(xml)} *main.xml\n")


def doubles():
    """5 x 4 doubles in bindata/data.bin, point (2, 1) invalid in bindata/valid.bin."""
    nx, ny, dx, dy = 5, 4, 2.5e-6, 5e-6
    z = [1e-6 * (0.5 * i - 0.25 * j) + 1e-7 * i * j for j in range(ny) for i in range(nx)]
    data = struct.pack(f"<{nx * ny}d", *z)
    valid = bytearray((nx * ny + 7) // 8)
    for k in range(nx * ny):
        if k != 2 + nx * 1:
            valid[k // 8] |= 1 << (k % 8)
    part = f"""  <DataLink>
   <PointDataLink>bindata/data.bin</PointDataLink>
   <MD5ChecksumPointData>{md5(data)}</MD5ChecksumPointData>
   <ValidPointsLink>bindata/valid.bin</ValidPointsLink>
   <MD5ChecksumValidPoints>{md5(bytes(valid))}</MD5ChecksumValidPoints>
  </DataLink>"""
    xml = main_xml(nx, ny, dx, dy, "D", part)
    write_x3p("doubles.x3p", xml, [("bindata/data.bin", data), ("bindata/valid.bin", bytes(valid))])


def inline_integers():
    """3 x 3 16-bit integers inline, z = 1e-6 + 2e-9 * (i + 3 j - 4), (1, 1) empty."""
    nx, ny = 3, 3
    datums = []
    for j in range(ny):
        for i in range(nx):
            datums.append("<Datum/>" if (i, j) == (1, 1) else f"<Datum>{i + 3 * j - 4}</Datum>")
    part = "  <DataList>\n   " + "\n   ".join(datums) + "\n  </DataList>"
    xml = main_xml(nx, ny, 1e-5, 2e-5, "I", part, "<Increment>2e-9</Increment><Offset>1e-6</Offset>")
    write_x3p("inline_integers.x3p", xml, [])


def floats():
    """4 x 3 32-bit floats, a NaN at (3, 2), z = (i - j) / 8 micrometres."""
    nx, ny = 4, 3
    z = [float("nan") if (i, j) == (3, 2) else (i - j) / 8 * 1e-6 for j in range(ny) for i in range(nx)]
    data = struct.pack(f"<{nx * ny}f", *z)
    part = f"""  <DataLink>
   <PointDataLink>bindata/data.bin</PointDataLink>
   <MD5ChecksumPointData>{md5(data).upper()}</MD5ChecksumPointData>
  </DataLink>"""
    xml = main_xml(nx, ny, 1e-6, 1e-6, "F", part)
    write_x3p("floats.x3p", xml, [("bindata/data.bin", data)])


def sdf_ascii():
    """4 x 3 in nanometres (Zscale 1e-9), z = 10 i - 7 j, (0, 2) BAD."""
    lines = ["aBCR-1.0", "ManufacID   = make.py", "CreateDate  = 010120240000",
             "ModDate     = 010120240000", "NumPoints   = 4", "NumProfiles = 3",
             "Xscale      = 5.0E-07", "Yscale      = 1.0E-06", "Zscale      = 1.0E-09",
             "Zresolution = -1", "Compression = 0", "DataType    = 5", "CheckType   = 0", "*"]
    for j in range(3):
        lines.append("  ".join("BAD" if (i, j) == (0, 2) else str(10 * i - 7 * j) for i in range(4)))
    lines += ["*", "<Comment>test data</Comment>", "*"]
    with open(os.path.join(HERE, "ascii.sdf"), "w", newline="\r\n") as f:
        f.write("\n".join(lines) + "\n")


def sdf_binary():
    """3 x 2 int16 in units of 2 nm, z = 100 i + 1000 j - 50, (2, 0) invalid (-32768)."""
    nx, ny = 3, 2
    header = b"bISO-1.0" + b"make.py".ljust(10) + b"010120240000" * 2
    header += struct.pack("<HHddddBBB", nx, ny, 1e-6, 1.5e-6, 2e-9, -1.0, 0, 5, 0)
    assert len(header) == 81
    values = [-32768 if (i, j) == (2, 0) else 100 * i + 1000 * j - 50 for j in range(ny) for i in range(nx)]
    with open(os.path.join(HERE, "binary.sdf"), "wb") as f:
        f.write(header + struct.pack(f"<{nx * ny}h", *values))


if __name__ == "__main__":
    doubles()
    inline_integers()
    floats()
    sdf_ascii()
    sdf_binary()
