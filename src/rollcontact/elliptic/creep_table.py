"""Kalker's creepage coefficients as a table: the data behind :mod:`rollcontact.elliptic.creep_coefficients`.

A data module (no logic) that a benchmark script regenerates from the discretised 3D solver at vanishing creepage;
its ``SOURCE`` says where the numbers come from.  Layout: ``ASPECT_RATIOS`` (a/b, increasing), ``POISSON_RATIOS``
(increasing), and for each coefficient a tuple per aspect ratio of values per Poisson ratio.  ``C33`` is None while
the table has no values for it.

Source of these values: J.J. Kalker, Three-Dimensional Elastic Bodies in Rolling Contact (Kluwer 1990), Table E.3
(the rows a/b = 0.1, 0.5, 1, 2, 10 as reprinted in the project's elliptic notes; the rows a/b > 1 are the table's
second block, g = b/a).
"""

SOURCE = "Kalker 1990, Table E.3 (rows a/b = 0.1, 0.5, 1, 2, 10)"

ASPECT_RATIOS = (0.1, 0.5, 1.0, 2.0, 10.0)
"""a/b [1] of the rows."""

POISSON_RATIOS = (0.0, 0.25, 0.5)
"""nu [1] of the columns."""

C11 = ((2.51, 3.31, 4.85),
       (2.88, 3.62, 4.83),
       (3.40, 4.12, 5.20),
       (4.37, 5.10, 6.11),
       (10.7, 11.7, 12.9))

C22 = ((2.51, 2.52, 2.53),
       (2.88, 3.01, 3.14),
       (3.40, 3.67, 3.98),
       (4.37, 4.90, 5.56),
       (10.7, 12.8, 16.0))

C23 = ((0.334, 0.473, 0.731),
       (0.827, 0.929, 1.07),
       (1.33, 1.47, 1.63),
       (2.35, 2.62, 2.96),
       (12.2, 14.6, 18.0))

C33 = None
