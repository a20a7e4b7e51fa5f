"""Print the OpenCV distributions installed beside opencv-contrib-python-headless (one per line).

Every OpenCV wheel writes the same ``cv2/`` folder, so a second one (mediapipe's declared GUI
build, say) leaves whichever was installed last; ``make install`` removes them and reinstalls
the headless contrib build.
"""

import importlib.metadata

OTHERS = ("opencv-python", "opencv-contrib-python", "opencv-python-headless")

for name in OTHERS:
    try:
        importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        continue
    print(name)
