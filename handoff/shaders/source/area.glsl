// ---- Rectangular lights: linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) with the same
// coefficients. The LTC table (ggx_ltc, `fresnel-lut build --ltc`) has the public tables' axes and packing (three.js
// LTC_Uv and ltc_1): u = r, v = sqrt(1 - NdotV), end points on texel centres, FRESNEL_LTC_SIZE texels a side.
vec2 fresnelLtcUV(float NdotV, float perceptualRoughness)
{
    float r = fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0);
    float mu = fresnelSanitize(NdotV, 1.0, 0.0, 1.0);
    return vec2(r, sqrt(1.0 - mu)) * ((FRESNEL_LTC_SIZE - 1.0) / FRESNEL_LTC_SIZE) + 0.5 / FRESNEL_LTC_SIZE;
}

// The same from sin(theta_v) = |N x V| as well: sqrt(1 - NdotV) = sin / sqrt(1 + NdotV), which float32 holds as
// NdotV -> 1, where this axis is steepest (1 - NdotV cancels: 0.016 texels of error, 3e-4 in a sharp lobe's light).
vec2 fresnelLtcUVSine(float NdotV, float sinV, float perceptualRoughness)
{
    float r = fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0);
    float mu = fresnelSanitize(NdotV, 1.0, 0.0, 1.0);
    float root = (mu > 0.0) ? min(sinV / sqrt(1.0 + mu), 1.0) : 1.0;
    return vec2(r, root) * ((FRESNEL_LTC_SIZE - 1.0) / FRESNEL_LTC_SIZE) + 0.5 / FRESNEL_LTC_SIZE;
}

// Lambert's edge vector (p x q) theta / (|p| |q| sin theta) of the directions p, q (any lengths), theta the angle
// between them: p x (q - p), the same vector, which float32 holds where p x q would cancel (a light 1e-3 wide two units
// away within 9.1e-5 of its largest value, not 3.8e-3, tests/luts/test_shaders_area.py), times theta / sin theta from
// the polynomial FRESNEL_LTC_EDGE in u = 1 - cos theta (preintegrate.ltc.edge_factor: within float32's rounding, and
// cheaper than atan; its constant 1 added last, which keeps a short edge's factor as close as 1 itself), beyond a right
// angle pi / sin theta less it at 1 + cos theta, sin theta from the cross product (1 - cos^2 would cancel); 0 where
// p x q is; the floors keep a point at the origin finite.
vec3 fresnelLtcEdge(vec3 p, vec3 q)
{
    vec3 c = cross(p, q - p);
    float d = dot(p, q);
    float inverseLengths = inversesqrt(max(dot(p, p) * dot(q, q), 1e-37));
    float u = 1.0 - abs(d) * inverseLengths;
    float near = ({{edge_factor}}) * inverseLengths;
    return c * ((d >= 0.0) ? near : 3.14159265 * inversesqrt(max(dot(c, c), 1e-37)) - near);
}

vec3 fresnelLtcUnit(vec3 v)
{
    return v * inversesqrt(max(dot(v, v), 1e-37));
}

// The view's part across the normal N (unit), V - N (N.V), taken twice (float32 leaves a part along N that dominates a
// short tangent): |N x V| long, the LTC frame's T1 once normalised.
vec3 fresnelLtcTangent(vec3 N, vec3 V)
{
    vec3 T1 = V - N * dot(V, N);
    return T1 - N * dot(T1, N);
}

// The view in the LTC's frame, (sin, 0, cos) with cos = N.V clamped to [0, 1] and sin = |N x V| (sqrt(1 - NdotV^2)
// would be float32's rounding of N.V near the normal, 3e-4); a view below the horizon is taken to it, (1, 0, 0).
vec3 fresnelLtcView(vec3 N, vec3 V)
{
    float c = dot(N, V);
    return vec3((c > 0.0) ? length(fresnelLtcTangent(N, V)) : 1.0, 0.0, clamp(c, 0.0, 1.0));
}

// M^-1 of the table's (m00, m20, m02, m22) applied to w, given in the shading frame (T1, T2, N): the LTC's
// M^-1 = [[m00, 0, m02], [0, 1, 0], [m20, 0, m22]], written out (no matrix type: the three languages order them
// differently).
vec3 fresnelLtcTransform(vec4 t, vec3 w)
{
    return vec3(t.x * w.x + t.z * w.z, w.y, t.y * w.x + t.w * w.z);
}

// The point where the segment a -> b crosses a plane through the origin, given its ends' heights above the plane
// (which run linearly along it); a where the heights are equal.
vec3 fresnelLtcCrossing(vec3 a, vec3 b, float heightA, float heightB)
{
    float denominator = heightA - heightB;
    return a + (b - a) * (heightA / ((denominator != 0.0) ? denominator : 1.0));
}

// The vector form factor, in the cosine's space, of the quad w (shading frame, the normal along z) clipped to the
// surface's horizon and then to the cosine's: (1/pi) times the integral of the direction over it (Arvo 1994; Heitz
// 2016 eq. 11 per component). Each clip runs edge by edge (an edge wholly below becomes a point, which adds nothing)
// and closes the clipped polygon along its plane from the exit to the entry point (around a closed polygon the heights
// change sign as often downward as upward; where they never do, the closing edge stays a point at the origin). The
// first clip takes the heights in the shading frame and the points through the table's M^-1 (t; it is linear), so its
// clipped edges and closing edge are five edges in the cosine's space for the second. Its z is the integral of the LTC
// over the part of the quad above the surface (the BRDF is zero below, where the LTC need not be), its direction the
// quad's mean direction there. Positive z when the corners turn counter-clockwise seen from the point that the quad
// lights, as three.js winds them.
vec3 fresnelLtcClippedVector(vec4 t, vec3 w[4])
{
    vec3 q[4];
    for (int i = 0; i < 4; ++i)
    {
        q[i] = fresnelLtcTransform(t, w[i]);
    }
    vec3 starts[5];
    vec3 ends[5];
    vec3 exitPoint = vec3(0.0);
    vec3 entryPoint = vec3(0.0);
    for (int i = 0; i < 4; ++i)
    {
        float heightA = w[i].z;
        float heightB = w[(i + 1) & 3].z;
        vec3 x = fresnelLtcCrossing(q[i], q[(i + 1) & 3], heightA, heightB);
        starts[i] = (heightA >= 0.0) ? q[i] : x;
        ends[i] = (heightB >= 0.0) ? q[(i + 1) & 3] : x;
        exitPoint = (heightA >= 0.0 && heightB < 0.0) ? x : exitPoint;
        entryPoint = (heightA < 0.0 && heightB >= 0.0) ? x : entryPoint;
    }
    starts[4] = exitPoint;
    ends[4] = entryPoint;
    vec3 sum = vec3(0.0);
    bool crosses = false;
    for (int i = 0; i < 5; ++i)
    {
        vec3 a = starts[i];
        vec3 b = ends[i];
        vec3 x = fresnelLtcCrossing(a, b, a.z, b.z);
        if (a.z >= 0.0 || b.z >= 0.0)  // the edge evaluations are the cost: skip what adds nothing
        {
            sum += fresnelLtcEdge((a.z >= 0.0) ? a : x, (b.z >= 0.0) ? b : x);
        }
        exitPoint = (a.z >= 0.0 && b.z < 0.0) ? x : exitPoint;
        entryPoint = (a.z < 0.0 && b.z >= 0.0) ? x : entryPoint;
        crosses = crosses || (a.z < 0.0 && b.z >= 0.0);
    }
    if (crosses)
    {
        sum += fresnelLtcEdge(exitPoint, entryPoint);
    }
    return -sum * 0.159154943;  // 1 / (2 pi)
}

// x^(2^times), by squaring: the powers of the light's spread, of the horizon's share and of the Fresnel blend's weight
// are powers of two (their generated FRESNEL_LTC_*_SQUARINGS), which multiplies cost less than pow's exp2 and log2 on
// CPU rasterisers.
float fresnelLtcSquared(float x, int times)
{
    for (int i = 0; i < times; ++i)
    {
        x *= x;
    }
    return x;
}

// The LTC integral I of a rectangular light taken toward the lobe's own punctual limit: at most 1 (the normalised lobe
// integrates to 1), I (w + (1 - w) min(g(L) / D(L), R)), w = I^p, at least (1 - s^k) min(1, I / c) min(1, ratio / rho)
// for a light wider than the lobe, s = min(omega / solidAngle, 1) the light's spread (solidAngle from
// fresnelLtcDiskSolidAngle; preintegrate.ltc.lobe_spread, LOBE_SPREAD_POWER), R = max(R0, min(K sqrt(omega), S / I)) (issue
// 41; preintegrate.ltc.toward_lobe_limit and lobe_ratio_bound: R also bounds what the ratio multiplies of float32's
// rounding of I, which grows as the light shrinks), omega the light's solid angle as the LTC's Jacobian at L gives it,
// pi det^2 |f|^4 / |back|^3 (preintegrate.ltc.ltc_solid_angle),
// g the GGX lobe (height-correlated G2) normalised by its albedo E, D the LTC's density, both at the light's
// representative direction L (unit, the shading frame). From the vector form factor f in the cosine's space and
// back = |det| M f, with q = |f|^2 / |back|^2 and size = sqrt(omega / pi) (fresnelLtcRectVector's):
// pi D(L) = f.z |back|^3 / (det^2 |f|^4) (Heitz 2016 eq. 1-3) and
// pi g(L) = a2 / d^2 mu_i / (2 (mu_i Lambda'_o + mu_o Lambda'_i) E), so g / D = a2 det^2 q^2 back.z / (2 d^2 smith E
// f.z), where no factor is a power of the light's size (float32 holds a tiny light). d = sin^2(theta_h) +
// a2 cos^2(theta_h) from H's components (1 - cos^2 cancels in float32 for a sharp lobe); a2 = r^4, at least the
// fit's own floor (ALPHA_FLOOR^2).
float fresnelLtcTowardLobe(float integral, vec3 f, vec3 back, float det, float q, float size, vec3 L, vec3 view, float r, float albedo, float solidAngle)
{
    float NdotV = view.z;
    vec3 H = fresnelLtcUnit(view + L);
    float a2 = max(r * r * r * r, 1e-8);
    float d = H.x * H.x + H.y * H.y + a2 * H.z * H.z;
    float mu = max(L.z, 0.0);
    float smith = mu * sqrt(NdotV * NdotV * (1.0 - a2) + a2) + NdotV * sqrt(mu * mu * (1.0 - a2) + a2);
    float bound = max(FRESNEL_LTC_LOBE_RATIO_MAX, min(FRESNEL_LTC_LOBE_RATIO_PER_SIZE * size, FRESNEL_LTC_LOBE_SHARE_RAISED / max(integral, 1e-30)));
    float lobe = a2 * (det * q) * (det * q) * max(back.z, 0.0);
    float density = 2.0 * d * d * smith * albedo * f.z;
    float ratio = (albedo > 0.0 && f.z > 0.0) ? lobe / max(max(density, lobe / bound), 1e-30) : 1.0;
    float w = pow(min(integral, 1.0), FRESNEL_LTC_LOBE_WEIGHT_POWER);
    float spread = (solidAngle > 0.0) ? min(3.14159265 * size * size / solidAngle, 1.0) : 1.0;
    float wide = (1.0 - fresnelLtcSquared(spread, FRESNEL_LTC_SPREAD_SQUARINGS)) * min(integral / FRESNEL_LTC_SPREAD_SHARE, 1.0);
    w = max(w, wide * min(ratio / FRESNEL_LTC_SPREAD_RATIO, 1.0));
    return min(integral * (w + (1.0 - w) * ratio), 1.0);
}

// The integral taken toward the LTC's share above the shading horizon, H = (1 + n.z) / 2, n the unit normal (M's third
// row, (-m20, 0, m00) / det) of the plane the table's M^-1 (t, its determinant det) takes the horizon to:
// I (1 + (1/H - 1) min(I/H, 1)^m), at most 1, m = 2^FRESNEL_LTC_UPPER_SHARE_SQUARINGS (preintegrate.ltc.toward_upper_share,
// ltc_upper_share): the LTC's share below the horizon stands for lobe just above it, which only a light covering nearly
// all of the lobe holds; H at least 1e-3 (the shipped table's least is 0.52, at N.V 0).
float fresnelLtcTowardUpper(float integral, vec4 t, float det)
{
    float cosine = t.x * inversesqrt(max(t.x * t.x + t.y * t.y, 1e-37));
    float upper = max(0.5 + 0.5 * ((det < 0.0) ? -cosine : cosine), 1e-3);
    float share = fresnelLtcSquared(min(integral / upper, 1.0), FRESNEL_LTC_UPPER_SHARE_SQUARINGS);
    return min(integral * (1.0 + (1.0 / upper - 1.0) * share), 1.0);
}

// The solid angle of the quad with corners (world space) seen from P, as a disk seen on its axis with the quad's
// projected solid angle |c . a| / |c|^3 (c the quad's centre from P, a = (1/2) (v2 - v0) x (v3 - v1) its vector area),
// 2 pi (1 - 1 / root), root = sqrt(1 + that / pi), written without the difference (preintegrate.ltc.disk_solid_angle:
// exact as the light shrinks, a little above a rectangle's exact solid angle, which would cost more); the vectors
// scaled by 1 / |c| first (float32 holds a far or huge light; 0 where |c| overflows).
float fresnelLtcDiskSolidAngle(vec3 P, vec3 corners[4])
{
    vec3 centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]) - P;
    float inverseDistance = inversesqrt(max(dot(centre, centre), 1e-37));
    vec3 area = 0.5 * cross((corners[2] - corners[0]) * inverseDistance, (corners[3] - corners[1]) * inverseDistance);
    float projected = abs(dot(centre * inverseDistance, area));
    float root = sqrt(1.0 + projected * 0.318309886);
    return 2.0 * projected / (root * (1.0 + root));
}

// A rectangular light as fresnelLtcRectLight gives it.
struct FresnelLtcLight
{
    vec4 light;  // the representative direction L (xyz) and the integral I (w)
    float spread;  // r', the roughness of the lobe whose Fresnel average stands for the light's
};

// The LTC of a rectangular light with corners (world space) seen from P with normal N and view V: the frame T1 (the
// view's tangential part), T2 = N x T1, N, then the table's M^-1. Returns the light's representative direction L in
// that frame (the direction of the transformed quad's vector form factor taken back through M) and, in w, the LTC
// integral (the share of the lobe the light covers), taken toward the lobe's punctual limit (fresnelLtcTowardLobe)
// and then toward the LTC's share above the horizon (fresnelLtcTowardUpper) for albedo E > 0, the LTC's own for
// albedo 0 (light); and r' = min(r, k sqrt(omega)), omega the light's solid angle as the LTC gives it: the roughness of
// the GGX lobe whose Fresnel average at V.H stands for the light's (spread; preintegrate.ltc.punctual_roughness).
FresnelLtcLight fresnelLtcRectLight(sampler2D ltcLut, vec3 N, vec3 V, vec3 P, vec3 corners[4], float r, float albedo)
{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    vec3 T1 = fresnelLtcTangent(N, V);
    float sinV = length(T1);  // |N x V|
    vec4 t = textureLod(ltcLut, fresnelAtlasLtc(fresnelLtcUVSine(NdotV, sinV, r)), 0.0);
    // a view within 1e-4 rad of the normal: any tangent (the LTC is isotropic there to float32's resolution)
    vec3 other = (abs(N.x) < 0.9) ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    T1 = (sinV > 1e-4) ? T1 : cross(N, other);
    T1 /= max(length(T1), 1e-30);
    vec3 T2 = cross(N, T1);
    vec3 local[4];
    for (int i = 0; i < 4; ++i)
    {
        vec3 w = corners[i] - P;
        local[i] = vec3(dot(w, T1), dot(w, T2), dot(w, N));
    }
    vec3 f = fresnelLtcClippedVector(t, local);
    // M = (M^-1)^-1 on the xz block, scaled by |det| (the direction is normalised): the adjugate times sign(det)
    float det = t.x * t.w - t.z * t.y;
    vec3 back = vec3(t.w * f.x - t.z * f.z, f.y * det, t.x * f.z - t.y * f.x) * ((det < 0.0) ? -1.0 : 1.0);
    vec3 L = fresnelLtcUnit(back);
    float integral = max(f.z, 0.0);
    float rough = fresnelSanitize(r, 0.5, 0.0, 1.0);
    float q = dot(f, f) / max(dot(back, back), 1e-30);
    float size = abs(det * q) * sqrt(sqrt(dot(back, back)));  // sqrt(omega / pi) = |det| q |back|^(1/2)
    FresnelLtcLight result;
    result.light = vec4(L, (albedo > 0.0) ? fresnelLtcTowardUpper(fresnelLtcTowardLobe(integral, f, back, det, q, size, L, fresnelLtcView(N, V), rough, albedo, fresnelLtcDiskSolidAngle(P, corners)), t, det) : integral);
    result.spread = min(rough, FRESNEL_LTC_PUNCTUAL_SPREAD * size);
    return result;
}

// fresnelLtcRectLight's light alone.
vec4 fresnelLtcRectVector(sampler2D ltcLut, vec3 N, vec3 V, vec3 P, vec3 corners[4], float r, float albedo)
{
    return fresnelLtcRectLight(ltcLut, N, V, P, corners, r, albedo).light;
}

// The LTC's own integral over a rectangular light (fresnelLtcRectVector's w for albedo 0).
float fresnelLtcRect(sampler2D ltcLut, vec3 N, vec3 V, vec3 P, vec3 corners[4], float r)
{
    return fresnelLtcRectVector(ltcLut, N, V, P, corners, r, 0.0).w;
}

// V.H*, H* along V + L, L the light's representative direction (fresnelLtcRectVector's; preintegrate.ltc.mean_half_v_dot_h),
// in the LTC's frame, the view from fresnelLtcView.
float fresnelLtcVdotH(vec4 light, vec3 view)
{
    return clamp(dot(view, fresnelLtcUnit(view + light.xyz)), 0.0, 1.0);
}

// The weight w = a I + (1 - a) I^n of the split sum in a rectangular light's Fresnel, I = light.w the share of the lobe
// the light covers (fresnelLtcRectVector; preintegrate.ltc.rect_light_fresnel), n = 2^FRESNEL_LTC_SPLIT_SUM_WEIGHT_SQUARINGS.
float fresnelLtcSplitSumWeight(vec4 light)
{
    float share = clamp(light.w, 0.0, 1.0);
    return FRESNEL_LTC_SPLIT_SUM_WEIGHT_LINEAR * share + (1.0 - FRESNEL_LTC_SPLIT_SUM_WEIGHT_LINEAR) * fresnelLtcSquared(share, FRESNEL_LTC_SPLIT_SUM_WEIGHT_SQUARINGS);
}

// Specular of a rectangular light per colour channel, from the same coefficients as the image-based and punctual
// paths: the LTC integral (taken toward the lobe's punctual limit with E, fresnelLtcRectLight) times
// E mix(F~, Fbar / E, w), F~ F averaged over the light: that of a GGX lobe of roughness r' (fresnelLtcRectLight) seen
// at V.H*, H* along V + L (fresnelLtcVdotH), and w from the share of the lobe it covers (fresnelLtcSplitSumWeight): a
// small light tends to the punctual limit F(V.H) of its direction, a light that covers the lobe to the split sum
// (issue 41). F~: {{rect_punctual_note}}
vec3 fresnelBasisRectLight(sampler2D ltcLut, sampler2D lut, sampler2D lut2, vec3 N, vec3 V, vec3 P, vec3 corners[4], float r, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    {{terms}} b = fresnelBasisTerms(lut, lut2, fresnelBasisLutUV(NdotV, r));
    FresnelLtcLight rect = fresnelLtcRectLight(ltcLut, N, V, P, corners, r, {{albedo}});
    vec4 light = rect.light;
    float spread = rect.spread;
    vec3 average = vec3(fresnelTermsDot(cR, b), fresnelTermsDot(cG, b), fresnelTermsDot(cB, b));
    float VdotH = fresnelLtcVdotH(light, fresnelLtcView(N, V));
    vec3 punctual = {{rect_punctual}};
    return light.w * mix(punctual, average, fresnelLtcSplitSumWeight(light));
}

// Schlick's variant for comparison (the engines' F0 * scale + bias from the Schlick table, F90 = 1), on the same
// integral as fresnelBasisRectLight's (E the table's B), so that the two differ by their Fresnel alone.
vec3 fresnelSchlickRectLight(sampler2D ltcLut, sampler2D schlickLut, vec3 N, vec3 V, vec3 P, vec3 corners[4], float r, vec3 f0)
{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    float albedo = textureLod(schlickLut, fresnelAtlasSchlick(fresnelBasisLutUV(NdotV, r)), 0.0).z;
    return fresnelLtcRectVector(ltcLut, N, V, P, corners, r, albedo).w * fresnelSchlickSplitSum(schlickLut, NdotV, r, f0);
}

// Specular of a rectangular light for a linear model's weights: as fresnelBasisRectLight, with its exact split sum
// and F~ from the Schlick table, exact for the model too ({{linear_rect_punctual_note}}).
vec3 fresnelLinearRectLight(sampler2D ltcLut, sampler2D schlickLut, vec3 N, vec3 V, vec3 P, vec3 corners[4], float r, vec3 wR, vec3 wG, vec3 wB)
{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    vec4 t = textureLod(schlickLut, fresnelAtlasSchlick(fresnelBasisLutUV(NdotV, r)), 0.0);
    FresnelLtcLight rect = fresnelLtcRectLight(ltcLut, N, V, P, corners, r, t.z);
    vec4 light = rect.light;
    float spread = rect.spread;
    float VdotH = fresnelLtcVdotH(light, fresnelLtcView(N, V));
    vec3 punctual = {{linear_rect_punctual}};
    return light.w * mix(punctual, fresnelLinearWeigh(t, wR, wG, wB), fresnelLtcSplitSumWeight(light));
}
