"""spectral_stats.py FILE.spectral.exr: prints "integral mean_wavelength
flat_over_line" of the image's summed spectrum: its radiant integral, its
mean wavelength, and the mean per nm over 600-640 nm over the integral over
440-460 nm (-1 when that is 0). For the fluorescence tests (cli_fluor.sh,
cli_light_fluor.sh)."""
import re
import sys

import numpy as np
import OpenImageIO as oiio

inp = oiio.ImageInput.open(sys.argv[1])
names = list(inp.spec().channelnames)
px = np.asarray(inp.read_image("float"), dtype=np.float64)
inp.close()
chans = [(float(m.group(1).replace(',', '.')), i) for i, n in enumerate(names)
         for m in [re.match(r'S0\.([0-9,]+)nm$', n)] if m]
wl = np.array([c[0] for c in chans]); idx = [c[1] for c in chans]
width = (780.0 - 380.0) / len(wl)
s = px[..., idx].reshape(-1, len(wl)).sum(axis=0)   # the image's summed spectrum
total = s.sum() * width
mean_wl = (s * wl).sum() / s.sum()
flat = s[(wl > 600) & (wl < 640)].mean()
line = s[(wl > 440) & (wl < 460)].sum() * width
print("%.9g %.6f %.9g" % (total, mean_wl, flat / line if line > 0 else -1))
