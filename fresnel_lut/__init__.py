"""The application layer: the ``fresnel-lut`` command (``cli``, ``entry``, ``progress``), scene builds (``scene``),
the renderer (``render``) and the report (``report``). It calls :mod:`basis` and the integration core
:mod:`preintegrate`; neither of them imports it."""
