"""Everything about integrating Fresnel channels against GGX: distribution, quadrature, Monte Carlo,
channel sets, LUT tables, EXR I/O and the ``fresnel-lut`` command."""
