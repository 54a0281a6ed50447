// The tables' texture coordinates of (NdotV, perceptual roughness): u = x * scale + offset of the column coordinate
// x, v = clamp(r, lo, hi) * scale + offset (FRESNEL_LUT_COLUMNS, FRESNEL_LUT_ROWS: the half-texel remap of the
// end-point texels of the grid that wrote this include), so that both ends of both axes are read exactly.
vec2 fresnelBasisLutUV(float NdotV, float perceptualRoughness)
{
    float r = clamp(fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0), FRESNEL_LUT_ROWS.x, FRESNEL_LUT_ROWS.y);
    float x = {{column}};
    return vec2(x * FRESNEL_LUT_COLUMNS.x + FRESNEL_LUT_COLUMNS.y, r * FRESNEL_LUT_ROWS.z + FRESNEL_LUT_ROWS.w);
}

// The preintegrated terms bbar_k at uv, read at level 0 (a mipmapped table would otherwise be read at the level that
// screen-space derivatives pick).
{{terms}} fresnelBasisTerms(sampler2D lut, sampler2D lut2, vec2 uv)
{
    return {{fetch}};
}

// The split sum of the basis (Belcour, Bati, Barla 2020, eq. 5): Fbar = sum_k c_k bbar_k(mu_o, r) per colour channel.
vec3 fresnelBasisSplitSum(sampler2D lut, sampler2D lut2, float NdotV, float r, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    {{terms}} b = fresnelBasisTerms(lut, lut2, fresnelBasisLutUV(NdotV, r));
    return vec3(fresnelTermsDot(cR, b), fresnelTermsDot(cG, b), fresnelTermsDot(cB, b));
}

// The tables' coordinates of (x, r), x = N.V, where the grid holds r = 0 (fresnelBasisSmoothed,
// fresnelLinearSmoothed): both clamped to [0, 1] in one integer clamp of their bits each (fresnelUnitClamp: NaN to an
// end), not sanitised to a fallback as fresnelBasisLutUV does.
vec2 fresnelMirrorLutUV(float x, float r)
{
    x = fresnelUnitClamp(x, 1.0);
    return vec2({{mirror_column}} * FRESNEL_LUT_COLUMNS.x + FRESNEL_LUT_COLUMNS.y, fresnelUnitClamp(r, 1.0) * FRESNEL_LUT_ROWS.z + FRESNEL_LUT_ROWS.w);
}

// F averaged over a GGX lobe of perceptual roughness r seen at N.V = x, times the albedo E (the split sum of that lobe
// over its own albedo E' = b0, times E): at r = 0, the table's mirror row, the curve itself (E' = 1).
vec3 fresnelBasisSmoothed(sampler2D lut, sampler2D lut2, float x, float r, float albedo, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    {{terms}} b = fresnelBasisTerms(lut, lut2, fresnelMirrorLutUV(x, r));
    return vec3(fresnelTermsDot(cR, b), fresnelTermsDot(cG, b), fresnelTermsDot(cB, b)) * (albedo / max({{albedo}}, 1e-4));
}

// Schlick's split sum for comparison (Karis 2013): F0 * scale + bias from the Schlick table (R, G).
vec3 fresnelSchlickSplitSum(sampler2D schlickLut, float NdotV, float r, vec3 f0)
{
    vec4 scaleBias = textureLod(schlickLut, fresnelAtlasSchlick(fresnelBasisLutUV(NdotV, r)), 0.0);
    return f0 * scaleBias.x + vec3(scaleBias.y);
}

// The hemispherical average F_avg = sum_k c_k avg(b_k) (multiple-scattering compensation), clamped to [0, 1].
vec3 fresnelBasisAverage({{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    {{terms}} averages = {{averages}};
    vec3 average = vec3(fresnelTermsDot(cR, averages), fresnelTermsDot(cG, averages), fresnelTermsDot(cB, averages));
    return clamp(average, vec3(0.0), vec3(1.0));
}

// Multiple-scattering compensation (Kulla and Conty 2017; Fdez-Aguera 2019): the energy a single bounce loses,
// 1 - E, returns scaled by F_avg, for a single-scattering split sum, GGX's albedo E without Fresnel and F_avg.
vec3 fresnelCompensate(vec3 single, float albedo, vec3 average)
{
    float lost = 1.0 - clamp(albedo, 0.0, 1.0);
    return single + single * average / (vec3(1.0) - lost * average) * lost;
}

// The basis split sum compensated for multiple scattering. E is bbar_0 of the basis table itself (b_0 = 1), so the
// compensation reads no other table.
vec3 fresnelBasisMultipleScattering(sampler2D lut, sampler2D lut2, float NdotV, float r, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    {{terms}} b = fresnelBasisTerms(lut, lut2, fresnelBasisLutUV(NdotV, r));
    vec3 single = vec3(fresnelTermsDot(cR, b), fresnelTermsDot(cG, b), fresnelTermsDot(cB, b));
    return fresnelCompensate(single, {{albedo}}, fresnelBasisAverage(cR, cG, cB));
}

// The exact split sum of a linear model (weights w = (w0, w1, w2) per colour channel, fresnelLinear<Model>): the
// Schlick table's R, G and A preintegrate 1 - (1 - mu)^5, (1 - mu)^5 and mu (1 - mu)^6, so Fbar = dot(w, (R, G, A)).
vec3 fresnelLinearWeigh(vec4 t, vec3 wR, vec3 wG, vec3 wB)
{
    vec3 terms = vec3(t.x, t.y, t.w);
    return vec3(dot(wR, terms), dot(wG, terms), dot(wB, terms));
}

vec3 fresnelLinearSplitSum(sampler2D schlickLut, float NdotV, float r, vec3 wR, vec3 wG, vec3 wB)
{
    return fresnelLinearWeigh(textureLod(schlickLut, fresnelAtlasSchlick(fresnelBasisLutUV(NdotV, r)), 0.0), wR, wG, wB);
}

// fresnelBasisSmoothed for a linear model's weights, from the Schlick table (its B is E').
vec3 fresnelLinearSmoothed(sampler2D schlickLut, float x, float r, float albedo, vec3 wR, vec3 wG, vec3 wB)
{
    vec4 t = textureLod(schlickLut, fresnelAtlasSchlick(fresnelMirrorLutUV(x, r)), 0.0);
    return fresnelLinearWeigh(t, wR, wG, wB) * (albedo / max(t.z, 1e-4));
}

// A linear model's hemispherical average F_avg = dot(w, averages of its three functions), exact (20/21, 1/21, 1/126),
// clamped to [0, 1].
vec3 fresnelLinearAverage(vec3 wR, vec3 wG, vec3 wB)
{
    vec3 average = vec3(dot(wR, FRESNEL_LINEAR_AVERAGES), dot(wG, FRESNEL_LINEAR_AVERAGES), dot(wB, FRESNEL_LINEAR_AVERAGES));
    return clamp(average, vec3(0.0), vec3(1.0));
}

// A linear model's split sum compensated for multiple scattering: E is the Schlick table's B.
vec3 fresnelLinearMultipleScattering(sampler2D schlickLut, float NdotV, float r, vec3 wR, vec3 wG, vec3 wB)
{
    vec4 t = textureLod(schlickLut, fresnelAtlasSchlick(fresnelBasisLutUV(NdotV, r)), 0.0);
    return fresnelCompensate(fresnelLinearWeigh(t, wR, wG, wB), t.z, fresnelLinearAverage(wR, wG, wB));
}
