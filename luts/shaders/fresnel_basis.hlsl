// fresnel-basis: split-sum Fresnel from the preintegrated LUTs (HLSL, Shader Model 4+).
//
// Belcour, Bati, Barla 2020, eq. 5:  Fbar = sum_k c_k * bbar_k(mu_o, alpha)      (4 terms, one RGBA fetch)
// Karis 2013 (Schlick split sum):    Fbar = F0 * scale + bias                     (2 terms, one RG fetch)
//
// LUT convention (EXR header attribute fresnel:convention): column i holds sqrt(mu_o) = i / (width - 1),
// mu_o = dot(N, V); row j holds perceptual roughness r = j / (height - 1) (GGX alpha = r * r), row 0 first
// (upload the rows in file order), so both ends of both axes stand on a texel; FresnelLutCoordinates reads them
// through the half-texel remap u = (x * (size - 1) + 0.5) / size of x = (sqrt(mu_o), r), the size from the texture
// itself. Use a bilinear, clamp-to-edge sampler.
// ggx_basis_rgba.exr: R, G, B, A = bbar_0 .. bbar_3; ggx_schlick_rgb.exr: R = scale, G = bias, B = E = R + G (GGX albedo without Fresnel).
//
// A scene's tables (fresnel-lut scene) crop their rows to the roughness range lo..hi of their header
// (fresnel:roughness_range): pass (r - lo) / (hi - lo) as perceptualRoughness. A scene whose table holds a
// whole basis also writes fresnel_basis_scene.*, with that mapping built in.
//
// Coefficients c (one float4 per colour channel) come from the Python API or `fresnel-lut coeffs --json`
// and must belong to the basis whose hash is in the LUT header (fresnel:basis_hash).

float2 FresnelLutCoordinates(Texture2D<float4> lut, float NdotV, float perceptualRoughness)
{
    uint width, height;
    lut.GetDimensions(width, height);
    float2 size = float2(width, height);
    float2 x = float2(sqrt(saturate(NdotV)), saturate(perceptualRoughness));
    return (x * (size - 1.0) + 0.5) / size;
}

float3 FresnelBasisSplitSum(Texture2D<float4> basisLut, SamplerState linearClamp, float NdotV,
                            float perceptualRoughness, float4 cR, float4 cG, float4 cB)
{
    float4 b = basisLut.SampleLevel(linearClamp, FresnelLutCoordinates(basisLut, NdotV, perceptualRoughness), 0);
    return float3(dot(cR, b), dot(cG, b), dot(cB, b));
}

// Five to eight terms (fresnel-lut basis --terms K; build and scene builds write terms 4..K-1 as R, G, B, A of a
// second table <name>_2.exr): one more fetch. eR, eG, eB hold c4..c7; give 0 for the terms a K < 8 table
// lacks (a texture without G, B or A reads them as 0, 0 and 1).
float3 FresnelBasisSplitSum8(Texture2D<float4> basisLut, Texture2D<float4> basisLut2, SamplerState linearClamp,
                             float NdotV, float perceptualRoughness, float4 cR, float4 cG, float4 cB,
                             float4 eR, float4 eG, float4 eB)
{
    float2 uv = FresnelLutCoordinates(basisLut, NdotV, perceptualRoughness);  // one size: both tables' grid
    float4 b = basisLut.SampleLevel(linearClamp, uv, 0);
    float4 e = basisLut2.SampleLevel(linearClamp, uv, 0);
    return float3(dot(cR, b) + dot(eR, e), dot(cG, b) + dot(eG, e), dot(cB, b) + dot(eB, e));
}

float3 FresnelSchlickSplitSum(Texture2D<float4> schlickLut, SamplerState linearClamp, float NdotV,
                              float perceptualRoughness, float3 F0)
{
    // one texture type for the Schlick table in every function (R = scale, G = bias, B = E; a two-channel scene
    // table reads B as 0 and A as 1)
    float2 scaleBias = schlickLut.SampleLevel(linearClamp, FresnelLutCoordinates(schlickLut, NdotV, perceptualRoughness), 0).rg;
    return F0 * scaleBias.x + scaleBias.y;
}

// Multiple-scattering compensation (Fdez-Aguera 2019; Kulla and Conty 2017): E = the Schlick table's B channel
// (GGX albedo without Fresnel), Favg = sum_k c_k avg(b_k) with avg = basis.json "hemispherical_averages"
// (exact for coloured edge tints); the result is 1 in a white furnace.
float3 FresnelBasisMultipleScattering(Texture2D<float4> basisLut, Texture2D<float4> schlickLut, SamplerState linearClamp,
                                      float NdotV, float perceptualRoughness, float4 cR, float4 cG, float4 cB,
                                      float4 averages)
{
    float3 FssEss = FresnelBasisSplitSum(basisLut, linearClamp, NdotV, perceptualRoughness, cR, cG, cB);
    float Ems = 1.0 - schlickLut.SampleLevel(linearClamp, FresnelLutCoordinates(schlickLut, NdotV, perceptualRoughness), 0).b;
    float3 Favg = saturate(float3(dot(cR, averages), dot(cG, averages), dot(cB, averages)));
    return FssEss + FssEss * Favg / (1.0 - Ems * Favg) * Ems;
}
