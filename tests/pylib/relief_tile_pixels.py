"""A relief tile's pixels as the live view's page decodes them (docs/view.md "The relief"), for
the browser tests that check what the relief shows.

    rgb = tile_pixels(page, "/relief/0/0/0.png")  # rows x columns x 3, int32, row 0 at the top
"""
import base64

import numpy as np

# The page loads the tile as an image, draws it into a canvas of its size and returns the RGBA
# bytes base64-encoded (in slices: one String.fromCharCode call per 32 KiB).
TILE_JS = """async (url) => {
  const img = new Image();
  img.src = url;
  await img.decode();
  const c = document.createElement('canvas');
  c.width = img.width; c.height = img.height;
  const g = c.getContext('2d');
  g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let bin = '';
  for (let i = 0; i < d.length; i += 32768) bin += String.fromCharCode.apply(null, d.subarray(i, i + 32768));
  return [c.width, c.height, btoa(bin)];
}"""


def rgb_array(w, h, b64):
    """RGBA bytes of a w x h picture, base64-encoded, as an h x w x 3 int32 array."""
    return np.frombuffer(base64.b64decode(b64), dtype=np.uint8).reshape(h, w, 4)[:, :, :3].astype(np.int32)


def tile_pixels(page, url):
    """The tile at `url` as the page decodes it."""
    return rgb_array(*page.evaluate(TILE_JS, url))
