"""Reads the PNGs dynterrain writes (render/png_io: 8-bit RGBA, not interlaced) into pixels, for
the Python tests that check what a render shows. Only the standard library: no imaging package
is needed on the test machine.

    image = PngImage.read("map.png"); r, g, b, a = image.pixel(column, row)  # row 0 at the top
"""
import struct
import zlib


class PngImage:
    def __init__(self, width, height, rows):
        self.width, self.height, self.rows = width, height, rows  # rows: bytes, 4 per pixel

    @staticmethod
    def read(path):
        data = open(path, "rb").read()
        if data[:8] != b"\x89PNG\r\n\x1a\n":
            raise ValueError(f"{path} is not a PNG")
        pos, header, idat = 8, None, b""
        while pos < len(data):
            length, kind = struct.unpack(">I4s", data[pos:pos + 8])
            body = data[pos + 8:pos + 8 + length]
            pos += 12 + length
            if kind == b"IHDR":
                header = struct.unpack(">IIBBBBB", body)
            elif kind == b"IDAT":
                idat += body
            elif kind == b"IEND":
                break
        if header is None:
            raise ValueError(f"{path} has no IHDR")
        width, height, depth, colour, _, _, interlace = header
        if (depth, colour, interlace) != (8, 6, 0):
            raise ValueError(f"{path}: bit depth {depth}, colour type {colour}, interlace "
                             f"{interlace}; only 8-bit RGBA, not interlaced, is read")
        raw, stride = zlib.decompress(idat), 4 * width
        rows, previous = [], bytes(stride)
        for r in range(height):
            start = r * (stride + 1)
            kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
            for i in range(stride):  # the five PNG filters, undone
                left = line[i - 4] if i >= 4 else 0
                up = previous[i]
                corner = previous[i - 4] if i >= 4 else 0
                if kind == 1:
                    line[i] = (line[i] + left) & 0xFF
                elif kind == 2:
                    line[i] = (line[i] + up) & 0xFF
                elif kind == 3:
                    line[i] = (line[i] + (left + up) // 2) & 0xFF
                elif kind == 4:
                    p = left + up - corner
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                    pred = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                    line[i] = (line[i] + pred) & 0xFF
                elif kind != 0:
                    raise ValueError(f"{path}: row {r} has filter type {kind}")
            rows.append(bytes(line))
            previous = line
        return PngImage(width, height, rows)

    def pixel(self, column, row):
        """(r, g, b, a) of pixel (column, row), row 0 at the top."""
        i = 4 * column
        return tuple(self.rows[row][i:i + 4])
