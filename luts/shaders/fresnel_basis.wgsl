// fresnel-basis: split-sum Fresnel from the preintegrated LUTs (WGSL, WebGPU).
//
// Belcour, Bati, Barla 2020, eq. 5:  Fbar = sum_k c_k * bbar_k(mu_o, alpha)      (4 terms, one RGBA fetch)
// Karis 2013 (Schlick split sum):    Fbar = F0 * scale + bias                     (2 terms, one RG fetch)
//
// LUT convention (EXR header attribute fresnel:convention): column i holds sqrt(mu_o) = i / (width - 1),
// mu_o = dot(N, V); row j holds perceptual roughness r = j / (height - 1) (GGX alpha = r * r), row 0 first
// (upload the rows in file order), so both ends of both axes stand on a texel; fresnelLutCoordinates reads them
// through the half-texel remap u = (x * (size - 1) + 0.5) / size of x = (sqrt(mu_o), r), the size from the texture
// itself. Sampler: linear filtering, clamp-to-edge, no mipmaps;
// the LUT is read at level 0 (textureSampleLevel). ggx_basis_rgba.exr: R, G, B, A = bbar_0 .. bbar_3 (A is
// signed: a float format); ggx_schlick_rgb.exr: R = scale, G = bias, B = E = R + G (GGX albedo without Fresnel). WebGPU filters rgba32float only with the
// "float32-filterable" feature: otherwise upload the half-float table as rgba16float.
//
// A scene's tables (fresnel-lut scene) crop their rows to the roughness range lo..hi of their header
// (fresnel:roughness_range): pass (r - lo) / (hi - lo) as perceptualRoughness. A scene whose table holds a
// whole basis also writes fresnel_basis_scene.*, with that mapping built in.
//
// Coefficients c (one vec4 per colour channel) come from the Python API or `fresnel-lut coeffs --json` and
// must belong to the basis whose hash is in the LUT header (fresnel:basis_hash).

fn fresnelLutCoordinates(lut: texture_2d<f32>, NdotV: f32, perceptualRoughness: f32) -> vec2<f32> {
    let size = vec2<f32>(textureDimensions(lut, 0));
    let x = vec2<f32>(sqrt(clamp(NdotV, 0.0, 1.0)), clamp(perceptualRoughness, 0.0, 1.0));
    return (x * (size - 1.0) + 0.5) / size;
}

fn fresnelBasisSplitSum(basisLut: texture_2d<f32>, linearClamp: sampler, NdotV: f32, perceptualRoughness: f32,
                        cR: vec4<f32>, cG: vec4<f32>, cB: vec4<f32>) -> vec3<f32> {
    let b = textureSampleLevel(basisLut, linearClamp, fresnelLutCoordinates(basisLut, NdotV, perceptualRoughness), 0.0);
    return vec3<f32>(dot(cR, b), dot(cG, b), dot(cB, b));
}

// Five to eight terms (fresnel-lut basis --terms K; build and scene builds write terms 4..K-1 as R, G, B, A of a
// second table <name>_2.exr): one more fetch. eR, eG, eB hold c4..c7; give 0 for the terms a K < 8 table
// lacks (a texture without G, B or A reads them as 0, 0 and 1).
fn fresnelBasisSplitSum8(basisLut: texture_2d<f32>, basisLut2: texture_2d<f32>, linearClamp: sampler, NdotV: f32,
                         perceptualRoughness: f32, cR: vec4<f32>, cG: vec4<f32>, cB: vec4<f32>, eR: vec4<f32>,
                         eG: vec4<f32>, eB: vec4<f32>) -> vec3<f32> {
    let uv = fresnelLutCoordinates(basisLut, NdotV, perceptualRoughness);  // one size: both tables' grid
    let b = textureSampleLevel(basisLut, linearClamp, uv, 0.0);
    let e = textureSampleLevel(basisLut2, linearClamp, uv, 0.0);
    return vec3<f32>(dot(cR, b) + dot(eR, e), dot(cG, b) + dot(eG, e), dot(cB, b) + dot(eB, e));
}

fn fresnelSchlickSplitSum(schlickLut: texture_2d<f32>, linearClamp: sampler, NdotV: f32, perceptualRoughness: f32,
                          F0: vec3<f32>) -> vec3<f32> {
    let scaleBias = textureSampleLevel(schlickLut, linearClamp, fresnelLutCoordinates(schlickLut, NdotV, perceptualRoughness), 0.0).rg;
    return F0 * scaleBias.x + scaleBias.y;
}

// Multiple-scattering compensation (Fdez-Aguera 2019; Kulla and Conty 2017): E = the Schlick table's B channel
// (GGX albedo without Fresnel), Favg = sum_k c_k avg(b_k) with avg = basis.json "hemispherical_averages"
// (exact for coloured edge tints); the result is 1 in a white furnace.
fn fresnelBasisMultipleScattering(basisLut: texture_2d<f32>, schlickLut: texture_2d<f32>, linearClamp: sampler,
                                  NdotV: f32, perceptualRoughness: f32, cR: vec4<f32>, cG: vec4<f32>, cB: vec4<f32>,
                                  averages: vec4<f32>) -> vec3<f32> {
    let FssEss = fresnelBasisSplitSum(basisLut, linearClamp, NdotV, perceptualRoughness, cR, cG, cB);
    let Ems = 1.0 - textureSampleLevel(schlickLut, linearClamp, fresnelLutCoordinates(schlickLut, NdotV, perceptualRoughness), 0.0).b;
    let Favg = clamp(vec3<f32>(dot(cR, averages), dot(cG, averages), dot(cB, averages)), vec3<f32>(0.0), vec3<f32>(1.0));
    return FssEss + FssEss * Favg / (1.0 - Ems * Favg) * Ems;
}
