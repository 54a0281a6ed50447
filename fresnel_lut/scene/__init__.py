"""Build for a scene: only the channels, roughness rows and tables its materials need.

Public objects: ``SceneError``, ``SceneMaterial``, ``Scene``, ``read_scene``, ``DEFAULT_TOLERANCE`` (:mod:`.files`);
``Layout`` (:mod:`.layout`); ``plan_scene``, ``ScenePlan`` (:mod:`.plan`); ``write_scene``, ``build_scene`` (:mod:`.write`).

A scene file (TOML or JSON) lists materials, each with the roughness range it is used at, and an error
tolerance on F̄ (default 1/255) and a working colour space::

    tolerance = 0.0039          # optional: max |F̄ − F̄_exact| over every material's range, all view angles
    space = "ACEScg"            # optional: colour space of presets
    size = 128                  # optional: LUT columns (μo); unset, the plan picks 128 or 256

    [[material]]
    name = "floor"
    preset = "Gold"             # or eta/kappa, reflectivity/edge_tint, f0 (Schlick), f0 + f82,
    roughness = [0.3, 0.6]      # or model = "generalized-adobe" with its parameters
                                # a number, a [low, high] range

**Exact target of a material**: its own model — the spectral RGB curve of a preset (Hoffman's procedure),
the Fresnel equations of (η, κ) or of Gulbrandsen's (r, g), Schlick for ``f0`` alone, Hoffman 2019 for
``f0`` + ``f82``, any model of :data:`basis.models.FRESNEL_MODELS` for ``model``.

**Candidate layouts** of a material: the Schlick table with F0 = F(0°) (exact for the Schlick family),
the first K generic basis terms (K = 2, 3, 4) with least-squares coefficients on them (c0 = F0 and
c0 + c1 = F90 kept exact), a **scene basis** — four terms trained on the scene's own curves (every channel
of every material), refined to minimise the worst error of F̄ over each material's roughness range
(:func:`basis.training.refine_basis`), with four-point coefficients at its own fit angles; then five, six,
… up to eight terms while the trained error stays above half of one 10-bit step (terms 4–7 go to a second
RGBA table, ``<name>_2.exr``) — and, for a material given by a linear model of the references (F0 + F82,
Adobe, generalized Schlick, …), that model's own exact split-sum table (``build --model``; exact while its
clamp is inactive). The scene basis is written beside its tables as ``scene_basis.json`` (curves, fit
angles, content hash; every table and material entry names that hash), so the coefficients and the table
always travel together. Every scene comes with the shader include generated for its grid (:mod:`handoff.shaders`:
``fresnelBasisLutUV`` on the cropped rows, the split sums, and the per-pixel coefficients and direct light of the
scene's own basis where a table holds it, else of the generic one; not the per-pixel tables' functions, since no such
tables exist for a scene's basis), ``fresnel_basis_scene.{glsl,hlsl,wgsl}``, named
apart from the default build's ``fresnel_basis.*`` so that a scene written beside a build never replaces that
build's include, and listed in ``scene_coefficients.json`` as ``shader_includes``.
**Path**: each material's entry in ``scene_coefficients.json`` and the report say which path it takes and why
(:meth:`fresnel_lut.scene.ScenePlan.path`: README's rule, an exact table for a linear model's curve, the basis for a
physical one, and where the scene's own basis holds a linear model as closely, the table it spares).
**Accuracy first**: a material that some layout holds to one 10-bit step
(:data:`fresnel_lut.scene.plan.ACCURACY_GOAL`, 1/1023) is held to it; the others to the tolerance.
**Tables**: any combination of the Schlick table, one basis table (generic or the scene's) and the models'
own tables; the one with the fewest channels that holds every material to its aim with one of its layouts,
then the fewest tables, then the most accurate. **Rows**: cropped to the union of the
materials' roughness ranges, endpoint-inclusive (row j ↔ r = r_lo + j (r_hi − r_lo)/(H − 1)), with
the fewest rows H ∈ {2, 3, 5, 9, 17, …} that still hold every material to its aim. **Columns**: the
file's ``size``; unset, 128 (the default build's), doubled to 256 when reading some material's exact F̄
bilinearly between 128 columns alone costs more than half of one 10-bit step
(:func:`fresnel_lut.scene.plan.lookup_floor`; near-mirrors at grazing: a clear coat at r = 0.05, 1.3e-3). The
columns stand where the default build's do, √μo = i/(size − 1): μo = 0 and 1 on a texel, the columns crowding
at grazing, where the split sum of a smooth surface steepens. A
Schlick-only scene trains no scene basis: Schlick's two channels hold it exactly.

**Error** is measured where it matters: at the 2 × size − 1 view cosines of the columns and the
midpoints in √μo between them (μo from 0 to 1: every lookup a GPU makes reads between two columns, none is
clamped to an edge texel), at the roughnesses of a 33-point grid over the scene's range that fall in
each material's own range (plus its end points), with bilinear, clamp-to-edge
interpolation of the table as a GPU does, against the split sum of the exact target. Every split sum is
a linear functional of the curve, computed with the texel weights of
:func:`preintegrate.quadrature.texel_weights`.

References
----------
:cite:`Belcour2020` eq. 5 (F̄ = Σ c_k b̄_k); :cite:`Karis2013` (Schlick split sum).
"""

from .files import DEFAULT_TOLERANCE, Scene, SceneError, SceneMaterial, read_scene
from .layout import Layout
from .plan import ScenePlan, plan_scene
from .write import build_scene, write_scene

__all__ = [
    "DEFAULT_TOLERANCE",
    "Layout",
    "Scene",
    "SceneError",
    "SceneMaterial",
    "ScenePlan",
    "plan_scene",
    "build_scene",
    "read_scene",
    "write_scene",
]
