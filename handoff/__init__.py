"""The hand-off to engines: what a build writes and ships — the tables in EXR, KTX2, 16-bit PNG and C headers
(``exr``, ``formats``), the list of tables a build writes and their one writer (``tables``), the shipped files'
names, headers and readers (``shipped``), and the shader include generated from the basis and the tables' grid
(``shaders``). It stands on :mod:`basis` and :mod:`preintegrate` (the integrals, which never import it) and never
imports the application layer (:mod:`fresnel_lut`)."""
