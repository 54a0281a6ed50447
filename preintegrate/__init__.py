"""Everything about integrating Fresnel channels against GGX: the distribution (``ggx``), the deterministic
quadrature (``quadrature``), the Monte-Carlo and Hammersley estimators (``estimators``), channel sets
(``channels``), LUT tables and their lookup (``lut``), EXR I/O (``exr``), scene builds (``scene``), the
renderer (``render``) and the ``fresnel-lut`` command (``cli``); the report (``report``) stands apart."""
