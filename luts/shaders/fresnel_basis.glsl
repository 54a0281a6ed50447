// fresnel-basis: split-sum Fresnel from the preintegrated LUTs (GLSL 3.30+, 4.x, Vulkan; ES 3.00 / WebGL 2).
//
// Belcour, Bati, Barla 2020, eq. 5:  Fbar = sum_k c_k * bbar_k(mu_o, alpha)      (4 terms, one RGBA fetch;
//                                                                                 5 to 8 terms, two)
// Karis 2013 (Schlick split sum):    Fbar = F0 * scale + bias                     (2 terms, one RG fetch)
//
// LUT convention (EXR header attribute fresnel:convention): column i holds sqrt(mu_o) = i / (width - 1),
// mu_o = dot(N, V); row j holds perceptual roughness r = j / (height - 1) (GGX alpha = r * r), row 0 first, so
// both ends of both axes stand on a texel; fresnelLutCoordinates reads them through the half-texel remap
// u = (x * (size - 1) + 0.5) / size of x = (sqrt(mu_o), r), the size from the texture itself. Sample with bilinear filtering and
// CLAMP_TO_EDGE. ggx_basis_rgba.exr: R, G, B, A = bbar_0 .. bbar_3; ggx_schlick_rgb.exr: R = scale, G = bias, B = E = R + G (GGX albedo without Fresnel).
// The LUT is read at level 0 (textureLod): texture() would pick a mip level from screen-space derivatives,
// and a mipmapped LUT (a common importer default) then returns wrong values at silhouettes. The A channel of
// the basis table is signed: upload a float format (RGBA16F or RGBA32F), never a unorm one.
// GLSL ES 3.00 / WebGL 2: declare "precision highp float; precision highp sampler2D;" before these lines
// (RGBA32F is not filterable there without OES_texture_float_linear: use the half-float table).
//
// A scene's tables (fresnel-lut scene) crop their rows to the roughness range lo..hi of their header
// (fresnel:roughness_range): pass (r - lo) / (hi - lo) as perceptualRoughness. A scene whose table holds a
// whole basis also writes fresnel_basis_scene.*, with that mapping built in.
//
// Coefficients c (one vec4 per colour channel) come from the Python API
// (basis.coefficients_from_nk / coefficients_from_gulbrandsen) or `fresnel-lut coeffs --json`; they must
// belong to the basis whose hash is in the LUT header (fresnel:basis_hash).

vec2 fresnelLutCoordinates(vec2 size, float NdotV, float perceptualRoughness)
{
    vec2 x = vec2(sqrt(clamp(NdotV, 0.0, 1.0)), clamp(perceptualRoughness, 0.0, 1.0));
    return (x * (size - 1.0) + 0.5) / size;
}

// Directional albedo of the Fresnel term for each colour channel (cR, cG, cB: coefficients c0..c3).
vec3 fresnelBasisSplitSum(sampler2D basisLut, float NdotV, float perceptualRoughness, vec4 cR, vec4 cG, vec4 cB)
{
    vec4 b = textureLod(basisLut, fresnelLutCoordinates(vec2(textureSize(basisLut, 0)), NdotV, perceptualRoughness), 0.0);
    return vec3(dot(cR, b), dot(cG, b), dot(cB, b));
}

// Five to eight terms (fresnel-lut basis --terms K; build and scene builds write terms 4..K-1 as R, G, B, A of a
// second table <name>_2.exr): one more fetch. eR, eG, eB hold c4..c7; give 0 for the terms a K < 8 table
// lacks (a texture without G, B or A reads them as 0, 0 and 1).
vec3 fresnelBasisSplitSum8(sampler2D basisLut, sampler2D basisLut2, float NdotV, float perceptualRoughness,
                           vec4 cR, vec4 cG, vec4 cB, vec4 eR, vec4 eG, vec4 eB)
{
    vec2 uv = fresnelLutCoordinates(vec2(textureSize(basisLut, 0)), NdotV, perceptualRoughness);  // one size: both tables' grid
    vec4 b = textureLod(basisLut, uv, 0.0);
    vec4 e = textureLod(basisLut2, uv, 0.0);
    return vec3(dot(cR, b) + dot(eR, e), dot(cG, b) + dot(eG, e), dot(cB, b) + dot(eB, e));
}

// Schlick's split sum for comparison: F0 per colour channel.
vec3 fresnelSchlickSplitSum(sampler2D schlickLut, float NdotV, float perceptualRoughness, vec3 F0)
{
    vec2 scaleBias = textureLod(schlickLut, fresnelLutCoordinates(vec2(textureSize(schlickLut, 0)), NdotV, perceptualRoughness), 0.0).rg;
    return F0 * scaleBias.x + scaleBias.y;
}

// Multiple-scattering compensation (Fdez-Aguera 2019; Kulla and Conty 2017): E = the Schlick table's B channel
// (GGX albedo without Fresnel), Favg = sum_k c_k avg(b_k) with avg = basis.json "hemispherical_averages"
// (exact for coloured edge tints); the result is 1 in a white furnace.
vec3 fresnelBasisMultipleScattering(sampler2D basisLut, sampler2D schlickLut, float NdotV, float perceptualRoughness,
                                    vec4 cR, vec4 cG, vec4 cB, vec4 averages)
{
    vec3 FssEss = fresnelBasisSplitSum(basisLut, NdotV, perceptualRoughness, cR, cG, cB);
    float Ems = 1.0 - textureLod(schlickLut, fresnelLutCoordinates(vec2(textureSize(schlickLut, 0)), NdotV, perceptualRoughness), 0.0).b;
    vec3 Favg = clamp(vec3(dot(cR, averages), dot(cG, averages), dot(cB, averages)), 0.0, 1.0);
    return FssEss + FssEss * Favg / (1.0 - Ems * Favg) * Ems;
}
