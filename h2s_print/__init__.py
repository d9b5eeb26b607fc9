"""h2s: printable step-by-step sketching workbooks from part-segmented 3D models.

After *How2Sketch: Generating Easy-To-Follow Tutorials for Sketching 3D Objects*
(Hennessey, Liu, Winnemöller, Dontcheva and Mitra, SIGGRAPH 2017), re-implemented.  The pipeline is a
chain of pure functions over frozen values; see ``README.md`` and the stage modules:

``load`` -> ``fit`` -> ``relate`` -> ``candidates`` -> ``select`` -> ``sequence`` ->
``project`` -> ``contours`` -> ``layout`` -> ``render``.
"""

from __future__ import annotations

__version__ = "0.1.0"
