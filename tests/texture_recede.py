"""A receding checkerboard plane at 1 spp (tests/cli_texture_aliasing.sh): the
image of a ground plane under a uniform sky of luminance 1, seen by a level
camera at height h, so the pixel row r rows below the horizon (r counted from
the horizon to the row's centre) sees the plane at distance h / (r p) and
a pixel there spans h / r across the view (p the pixel's angle), whatever
the field of view. usage: texture_recede.py IMAGE.exr SQUARE MEAN CONTRAST
(SQUARE the checker's square side over h, MEAN its mean linear value, CONTRAST
the difference of its two values). Prints, for the far rows (a pixel spans at
least one square across and dozens along the view) the mean, the RMS of the
pixels' and of the 4 x 4 blocks' deviation from MEAN (the aliasing), and for
the near rows (a pixel spans at most a quarter of a square) the pixels'
standard deviation over CONTRAST / 2 (1: a sharp board; 0: blurred to grey)."""
import sys, warnings
warnings.filterwarnings("ignore")
import numpy as np, OpenImageIO as oiio
img = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[..., :3].mean(axis=2)
square, mean, contrast = (float(a) for a in sys.argv[2:5])
h, w = img.shape
r = np.arange(h) + 0.5 - h / 2  # rows below the horizon, to the row's centre
far = img[(r >= 1.0) & (r <= 1.0 / square)]
near = img[r >= 4.0 / square]
if far.shape[0] < 4 or near.shape[0] < 4:
    sys.exit("the image has too few far or near rows for square %g" % square)
far = far[: far.shape[0] // 4 * 4, : w // 4 * 4]
blocks = far.reshape(far.shape[0] // 4, 4, -1, 4).mean(axis=(1, 3))
print("far_mean %.5f" % far.mean())
print("far_pixel_rms %.5f" % np.sqrt(((far - mean) ** 2).mean()))
print("far_block_rms %.5f" % np.sqrt(((blocks - mean) ** 2).mean()))
print("near_contrast %.5f" % (near.std() / (contrast / 2)))
