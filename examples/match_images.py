"""`seismo3d match`: HOG-pyramid matches between an image and the same image turned by 90 degrees.

Run:  python examples/match_images.py       (uses a photograph bundled with scikit-image)
The same on the command line:  seismo3d match camera.png camera_90.png -o matches.csv --method hog
"""

# %% Two images: scikit-image's camera and the same turned by 90 degrees (a known homography)
import numpy as np
import skimage.data
import skimage.io

from seismo3d.features import evaluate_matches, rotation_homography, warp_image
from seismo3d.jobs.match import run_match_job

image = skimage.data.camera()
h = rotation_homography(image.shape, 90)
turned, _ = warp_image(image, h)
skimage.io.imsave("camera.png", image)
skimage.io.imsave("camera_90.png", turned)

# %% Match with the HOG-pyramid (RANSAC homography), and score the matches against the known homography
for method in ("hog", "sift"):
    job = run_match_job("camera.png", "camera_90.png", f"matches_{method}.csv", method=method, overwrite=True)
    res = job.result
    score = evaluate_matches(res.xy1[res.inliers], res.xy2[res.inliers], h)
    print(f"{method}: {res.n_putative} putative matches, {job.n_written} verified, "
          f"{100 * score.fraction_correct:.0f} % of them within 3 pixels of the truth")
