//! common
// The look-development page's shaders (fresnel_lut/page/view.js puts "#version 300 es", the precision lines and the
// shipped include fresnel_basis.glsl before this text, verbatim). One programme per
// "//! name" section below, each after this common part. Float32 throughout; nothing here returns NaN or inf.

const float PI = 3.14159265358979;

uniform float u_size;  // the sphere's size in pixels: it fills a square, orthographic camera along -z (render.py)

// The material: u_kind 0 a preset (its sRGB coefficients and its exact curve as a 1024 x 1 table over mu),
// 1 eta and kappa per channel, 2 Gulbrandsen's reflectivity and edge tint, 3 F0 and F82 tint (Adobe / OpenPBR).
uniform int u_kind;
uniform vec3 u_a;  // eta | r | F0
uniform vec3 u_b;  // kappa | g | tint
uniform vec4 u_presetR, u_presetG, u_presetB;
uniform sampler2D u_curve;
uniform float u_roughness;  // perceptual r; GGX alpha = r^2

// The studio of fresnel_lut/render.py: L(w) = sum_i c_i exp(lambda_i (w.p_i - 1)).
const int MAX_LOBES = 8;
uniform int u_lobes;
uniform vec3 u_lobeAxis[MAX_LOBES];
uniform float u_lobeSharpness[MAX_LOBES];
uniform vec3 u_lobeAmplitude[MAX_LOBES];

vec3 studioRadiance(vec3 d)
{
    vec3 total = vec3(0.0);
    for (int i = 0; i < MAX_LOBES; ++i)
    {
        if (i >= u_lobes) break;
        total += exp(u_lobeSharpness[i] * (dot(d, u_lobeAxis[i]) - 1.0)) * u_lobeAmplitude[i];
    }
    return total;
}

// Karis's prefiltered radiance as render.py's Environment.prefiltered: L convolved with the normalised SG lobe of
// sharpness s = 1/(2 alpha^2) around d, in closed form. The exponent m - lambda - s is written as
// 2 lambda s (p.d - 1) / (m + lambda + s), since m ~ s ~ 5e7 at alpha = 1e-4 leaves nothing of the difference in float32.
vec3 studioPrefiltered(vec3 d, float alpha)
{
    float a = max(alpha, 1e-4);
    float s = 0.5 / (a * a);
    float norm = (1.0 - exp(-2.0 * s)) / s;
    vec3 total = vec3(0.0);
    for (int i = 0; i < MAX_LOBES; ++i)
    {
        if (i >= u_lobes) break;
        float lambda = u_lobeSharpness[i];
        float m = length(lambda * u_lobeAxis[i] + s * d);
        float e = 2.0 * lambda * s * (dot(u_lobeAxis[i], d) - 1.0) / (m + lambda + s);
        total += exp(e) * (1.0 - exp(-2.0 * m)) / max(m, 1e-30) / norm * u_lobeAmplitude[i];
    }
    return total;
}

// An equirectangular map (rows top first): u = atan(x, -z) / 2pi + 1/2, v = acos(y) / pi; texel (i, j) holds the
// direction at ((i + 1/2) / W, (j + 1/2) / H). Bilinear by hand (RGBA32F needs an extension to filter), wrapped in u.
vec2 equirectUV(vec3 d)
{
    return vec2(atan(d.x, -d.z) * (0.5 / PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

vec3 equirectDirection(vec2 uv)
{
    float phi = (uv.x - 0.5) * 2.0 * PI, theta = uv.y * PI;
    return vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// origin: the level's first texel in an atlas (the page stacks an environment's mip levels in one texture)
vec3 mapBilinear(sampler2D map, ivec2 origin, ivec2 size, vec2 uv)
{
    vec2 p = uv * vec2(size) - 0.5;
    vec2 f = p - floor(p);
    ivec2 i0 = ivec2(floor(p));
    int x0 = ((i0.x % size.x) + size.x) % size.x, x1 = (x0 + 1) % size.x;
    int y0 = clamp(i0.y, 0, size.y - 1), y1 = clamp(i0.y + 1, 0, size.y - 1);
    vec3 a = texelFetch(map, origin + ivec2(x0, y0), 0).rgb, b = texelFetch(map, origin + ivec2(x1, y0), 0).rgb;
    vec3 c = texelFetch(map, origin + ivec2(x0, y1), 0).rgb, e = texelFetch(map, origin + ivec2(x1, y1), 0).rgb;
    return mix(mix(a, b, f.x), mix(c, e, f.x), f.y);
}

// The preset's exact curve at mu (linear between its 1024 samples).
vec3 presetCurve(float mu)
{
    float x = clamp(mu, 0.0, 1.0) * 1023.0;
    int i = min(int(x), 1022);
    return mix(texelFetch(u_curve, ivec2(i, 0), 0).rgb, texelFetch(u_curve, ivec2(i + 1, 0), 0).rgb, x - float(i));
}

// The material's coefficients, per pixel from its parameters (the shipped include's functions).
void materialCoefficients(out vec4 cR, out vec4 cG, out vec4 cB)
{
    if (u_kind == 1)
    {
        fresnelCoefficientsNK3(u_a, u_b, cR, cG, cB);
    }
    else if (u_kind == 2)
    {
        fresnelCoefficientsGulbrandsen3(u_a, u_b, cR, cG, cB);
    }
    else if (u_kind == 3)
    {
        cR = fresnelCoefficientsF82Tint(u_a.r, u_b.r);
        cG = fresnelCoefficientsF82Tint(u_a.g, u_b.g);
        cB = fresnelCoefficientsF82Tint(u_a.b, u_b.b);
    }
    else
    {
        cR = u_presetR;
        cG = u_presetG;
        cB = u_presetB;
    }
}

// The material's exact curve at mu: what the reference and the punctual light's exact F use.
float gulbrandsenExact(float mu, float r, float g)
{
    vec2 nk2 = fresnelGulbrandsenToEtaKappa2(clamp(r, 0.0, 0.9999), clamp(g, 0.0, 1.0));
    return fresnelExact(mu, nk2.x, sqrt(nk2.y));
}

vec3 exactFresnel(float mu)
{
    if (u_kind == 1)
    {
        vec3 eta = clamp(u_a, 1e-4, 1e4), kappa = clamp(u_b, 0.0, 1e4);
        return vec3(fresnelExact(mu, eta.r, kappa.r), fresnelExact(mu, eta.g, kappa.g), fresnelExact(mu, eta.b, kappa.b));
    }
    if (u_kind == 2)
    {
        return vec3(gulbrandsenExact(mu, u_a.r, u_b.r), gulbrandsenExact(mu, u_a.g, u_b.g),
                    gulbrandsenExact(mu, u_a.b, u_b.b));
    }
    if (u_kind == 3)
    {
        return fresnelLinearDirect(mu, fresnelLinearF82Tint(u_a.r, u_b.r), fresnelLinearF82Tint(u_a.g, u_b.g),
                                   fresnelLinearF82Tint(u_a.b, u_b.b));  // the model itself, clamped to [0, 1]
    }
    return presetCurve(mu);
}

// Tone map and ΔE2000 of fresnel_lut/render.py and basis/colorimetry.py (the report's measure of a picture).
vec3 toneMap(vec3 x)
{
    x = max(x, 0.0);
    vec3 excess = max(x - 0.8, 0.0);
    return mix(x, 0.8 + 0.2 * excess / (excess + 0.2), greaterThan(x, vec3(0.8)));
}

uniform mat3 u_rgbToXyz;  // sRGB's published matrix (basis.colorimetry); white = its rows' sums
uniform vec3 u_white;

vec3 labOf(vec3 rgb)
{
    vec3 t = (u_rgbToXyz * rgb) / u_white;
    const float epsilon = 216.0 / 24389.0, kappa = 24389.0 / 27.0;
    vec3 f = mix((kappa * t + 16.0) / 116.0, pow(max(t, 1e-30), vec3(1.0 / 3.0)), greaterThan(t, vec3(epsilon)));
    return vec3(116.0 * f.y - 16.0, 500.0 * (f.x - f.y), 200.0 * (f.y - f.z));
}

float hueAngle(float b, float a)  // degrees in [0, 360)
{
    if (a == 0.0 && b == 0.0) return 0.0;
    float h = degrees(atan(b, a));
    return (h < 0.0) ? h + 360.0 : h;
}

// CIEDE2000 (Sharma, Wu, Dalal 2005, eq. 1-22; kL = kC = kH = 1).
float deltaE2000(vec3 lab1, vec3 lab2)
{
    float c7 = pow(0.5 * (length(lab1.yz) + length(lab2.yz)), 7.0);
    float g = 0.5 * (1.0 - sqrt(c7 / (c7 + 6103515625.0)));  // 25^7
    float a1 = (1.0 + g) * lab1.y, a2 = (1.0 + g) * lab2.y;
    float c1 = length(vec2(a1, lab1.z)), c2 = length(vec2(a2, lab2.z));
    float h1 = hueAngle(lab1.z, a1), h2 = hueAngle(lab2.z, a2);
    float product = c1 * c2;
    float dh = h2 - h1;
    dh = (product == 0.0) ? 0.0 : ((dh > 180.0) ? dh - 360.0 : ((dh < -180.0) ? dh + 360.0 : dh));
    float dL = lab2.x - lab1.x, dC = c2 - c1;
    float dH = 2.0 * sqrt(product) * sin(radians(0.5 * dh));
    float L = 0.5 * (lab1.x + lab2.x), C = 0.5 * (c1 + c2);
    float hs = h1 + h2;
    float H = (product == 0.0) ? hs : ((abs(h1 - h2) <= 180.0) ? 0.5 * hs : ((hs < 360.0) ? 0.5 * (hs + 360.0) : 0.5 * (hs - 360.0)));
    float T = 1.0 - 0.17 * cos(radians(H - 30.0)) + 0.24 * cos(radians(2.0 * H)) + 0.32 * cos(radians(3.0 * H + 6.0))
              - 0.2 * cos(radians(4.0 * H - 63.0));
    float dTheta = 30.0 * exp(-pow((H - 275.0) / 25.0, 2.0));
    float C7 = pow(C, 7.0);
    float rC = 2.0 * sqrt(C7 / (C7 + 6103515625.0));
    float l50 = (L - 50.0) * (L - 50.0);
    float sL = 1.0 + 0.015 * l50 / sqrt(20.0 + l50), sC = 1.0 + 0.045 * C, sH = 1.0 + 0.015 * C * T;
    float rT = -sin(radians(2.0 * dTheta)) * rC;
    float x = dL / sL, y = dC / sC, z = dH / sH;
    return sqrt(max(x * x + y * y + z * z + rT * y * z, 0.0));
}

float deltaEOfPictures(vec3 linearA, vec3 linearB)
{
    return deltaE2000(labOf(toneMap(linearA)), labOf(toneMap(linearB)));
}

// The first two dimensions of Sobol's sequence (van der Corput's radical inverse and Sobol's second generator), as
// 32-bit fractions: every power-of-two prefix is stratified; a random shift per pixel (Cranley-Patterson) keeps the
// estimate unbiased, as render.py's shifted lattice, and about halves the noise of independent samples.
uint vanDerCorput(uint bits)
{
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    return ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
}

uint sobolSecond(uint index)
{
    uint result = 0u;
    for (uint v = 1u << 31u; index != 0u; index >>= 1u, v ^= v >> 1u)
    {
        if ((index & 1u) != 0u) result ^= v;
    }
    return result;
}

//! shade
// One mode of the sphere into a float target: 0 Schlick's split sum, 1 the basis', 2 the basis' with multiple
// scattering, 3 the reference (u_samples more samples added to u_sum, u_squares).
uniform int u_mode;
uniform bool u_environmentOn, u_pointOn, u_rectOn;
uniform int u_environmentKind;  // 0 the studio in closed form, 1 the user's map (u_map, prefiltered u_prefiltered)
uniform sampler2D u_basisLut, u_schlickLut, u_ltcLut;
uniform sampler2D u_map, u_prefiltered;
uniform ivec2 u_mapSize, u_prefilteredSize;
uniform vec3 u_pointDirection;
uniform float u_pointRadiance;
uniform vec3 u_rectCorners[4];
uniform float u_rectRadiance;
uniform sampler2D u_sum, u_squares;
uniform int u_samples, u_sampleBase;
layout(location = 0) out vec4 o_value;
layout(location = 1) out vec4 o_squares;

// Smith's Lambda for GGX through sqrt(mu^2 + alpha^2 (1 - mu^2)), finite at the horizon (preintegrate/ggx.py).
float smithLambda(float mu, float alpha)
{
    mu = max(mu, 1e-6);
    return 0.5 * (sqrt(mu * mu + alpha * alpha * (1.0 - mu * mu)) / mu - 1.0);
}

// Schlick's (1 - cos)^5 as engines write it (three multiplications: Filament's pow5, HDRP, Unreal), not pow(),
// which SwiftShader and llvmpipe evaluate as exp2(5 log2(x)).
float schlickWeight(float cosine)
{
    float m = 1.0 - cosine, m2 = m * m;
    return m2 * m2 * m;
}

float ggxD(float muH, float alpha)  // Walter 2007 eq. 33
{
    float a2 = alpha * alpha;
    float d = muH * muH * (a2 - 1.0) + 1.0;
    return (muH > 0.0) ? a2 / (PI * d * d) : 0.0;
}

// GGX VNDF sampling (Heitz 2018, JCGT 7(4), listing 1) in the frame where N = +z.
vec3 sampleVndf(vec3 v, float alpha, float u1, float u2)
{
    vec3 vh = normalize(vec3(alpha * v.x, alpha * v.y, v.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = (lensq > 0.0) ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    float p1 = r * cos(phi), p2 = r * sin(phi);
    float s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(nh.z, 1e-7)));
}

// Jarzynski and Olano 2020, "Hash functions for GPU rendering" (pcg3d).
uvec3 pcg3d(uvec3 v)
{
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    return v;
}

vec3 environmentRadiance(vec3 d)
{
    return (u_environmentKind == 0) ? studioRadiance(d) : mapBilinear(u_map, ivec2(0), u_mapSize, equirectUV(d));
}

// The rectangular light seen along w from P: its radiance where the ray meets the lit side, else 0.
vec3 rectHit(vec3 P, vec3 w)
{
    vec3 e1 = u_rectCorners[1] - u_rectCorners[0], e2 = u_rectCorners[3] - u_rectCorners[0];
    vec3 n = cross(e1, e2);  // towards the lit side
    float facing = dot(w, n);
    if (facing >= 0.0 || dot(P - u_rectCorners[0], n) <= 0.0) return vec3(0.0);
    float t = dot(u_rectCorners[0] - P, n) / facing;
    vec3 q = P + t * w - u_rectCorners[0];
    float s = dot(q, e1) / dot(e1, e1), u = dot(q, e2) / dot(e2, e2);
    return (t > 0.0 && s >= 0.0 && s <= 1.0 && u >= 0.0 && u <= 1.0) ? vec3(u_rectRadiance) : vec3(0.0);
}

void main()
{
    vec2 p = gl_FragCoord.xy / u_size * 2.0 - 1.0;
    float radius2 = dot(p, p);
    if (radius2 >= 1.0)
    {
        o_value = vec4(0.0);
        o_squares = vec4(0.0);
        return;
    }
    vec3 N = vec3(p, sqrt(max(1.0 - radius2, 0.0)));
    vec3 V = vec3(0.0, 0.0, 1.0);
    float NdotV = clamp(N.z, 0.0, 1.0);
    float r = clamp(u_roughness, 0.0, 1.0);
    float alpha = r * r;
    vec4 cR, cG, cB;
    materialCoefficients(cR, cG, cB);
    vec3 f0 = exactFresnel(1.0);

    // the punctual light (render.py's render_point_light): L rho mu_l = L D G2 F / (4 mu_o)
    vec3 point = vec3(0.0);
    if (u_pointOn)
    {
        vec3 L = normalize(u_pointDirection);
        vec3 H = normalize(V + L);
        float NdotL = clamp(dot(N, L), 0.0, 1.0), NdotH = clamp(dot(N, H), 0.0, 1.0), VdotH = clamp(dot(V, H), 0.0, 1.0);
        float a = max(alpha, 1e-6);
        float brdfCos = (NdotV > 0.0 && NdotL > 0.0)
            ? ggxD(NdotH, a) / (1.0 + smithLambda(NdotV, a) + smithLambda(NdotL, a)) / (4.0 * NdotV) : 0.0;
        vec3 F = (u_mode == 0) ? f0 + (1.0 - f0) * schlickWeight(VdotH)
               : ((u_mode == 3) ? exactFresnel(VdotH) : fresnelBasisDirect(VdotH, cR, cG, cB));
        point = u_pointRadiance * brdfCos * F;
    }

    if (u_mode == 3)
    {
        // Monte Carlo of the exact BRDF with the exact curve (render.py's render_reference): VNDF samples,
        // weight F(o.h) G2 / G1; the point light added to every sample (it needs no integral)
        float muO = clamp(N.z, 1e-6, 1.0);
        vec3 T = V - muO * N;
        float length2 = dot(T, T);
        vec3 fallback = (abs(N.x) < 0.9) ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        T = (length2 > 1e-18) ? T * inversesqrt(length2) : normalize(fallback - dot(fallback, N) * N);
        vec3 B = cross(N, T);
        vec3 o = vec3(sqrt(max(1.0 - muO * muO, 0.0)), 0.0, muO);
        float a = max(alpha, 1e-6);
        float g1 = 1.0 / (1.0 + smithLambda(muO, a));
        vec3 sum = vec3(0.0), squares = vec3(0.0);
        vec2 shift = vec2(pcg3d(uvec3(uvec2(gl_FragCoord.xy), 0x9e3779b9u)).xy >> 8u) * (1.0 / 16777216.0);
        for (int k = 0; k < u_samples; ++k)
        {
            uint index = uint(u_sampleBase + k);
            vec2 u = fract(vec2(float(vanDerCorput(index) >> 8u), float(sobolSecond(index) >> 8u)) * (1.0 / 16777216.0)
                           + shift);
            vec3 m = sampleVndf(o, a, u.x, u.y);
            float oh = dot(o, m);
            vec3 i = 2.0 * oh * m - o;
            vec3 value = point;
            if (i.z > 0.0)
            {
                float weight = (1.0 / (1.0 + smithLambda(muO, a) + smithLambda(i.z, a))) / g1;
                vec3 w = normalize(i.x * T + i.y * B + i.z * N);
                vec3 radiance = (u_environmentOn ? environmentRadiance(w) : vec3(0.0)) + (u_rectOn ? rectHit(N, w) : vec3(0.0));
                value += exactFresnel(clamp(oh, 0.0, 1.0)) * weight * radiance;
            }
            sum += value;
            squares += value * value;
        }
        ivec2 pixel = ivec2(gl_FragCoord.xy);
        o_value = texelFetch(u_sum, pixel, 0) + vec4(sum, float(u_samples));
        o_squares = texelFetch(u_squares, pixel, 0) + vec4(squares, 0.0);
        return;
    }

    vec3 color = point;
    if (u_environmentOn)
    {
        vec3 R = 2.0 * NdotV * N - V;
        vec3 prefiltered = (u_environmentKind == 0) ? studioPrefiltered(R, alpha)
                                                     : mapBilinear(u_prefiltered, ivec2(0), u_prefilteredSize, equirectUV(R));
        vec3 Fbar = (u_mode == 0) ? fresnelSchlickSplitSum(u_schlickLut, NdotV, r, f0)
                  : ((u_mode == 1) ? fresnelBasisSplitSum(u_basisLut, NdotV, r, cR, cG, cB)
                                   : fresnelBasisMultipleScattering(u_basisLut, NdotV, r, cR, cG, cB));
        color += prefiltered * Fbar;
    }
    if (u_rectOn)
    {
        color += u_rectRadiance * ((u_mode == 0) ? fresnelSchlickRectLight(u_ltcLut, u_schlickLut, N, V, N, u_rectCorners, r, f0)
                                                 : fresnelBasisRectLight(u_ltcLut, u_basisLut, N, V, N, u_rectCorners, r, cR, cG, cB));
    }
    o_value = vec4(color, 1.0);
    o_squares = vec4(0.0);
}

//! prefilter
// The user's map convolved with the normalised SG lobe of sharpness s = 1/(2 alpha^2) (the studio's definition),
// by u_count von Mises-Fisher samples per texel (a Hammersley set) read from the map's mip level whose texel
// matches the sample's solid angle (filtered importance sampling, Krivanek and Colbert 2008).
uniform sampler2D u_atlas;  // the map's mip levels stacked: level l at (0, u_levelRow[l]), size (W >> l, H >> l)
uniform ivec2 u_mapSize;
uniform int u_levels;
uniform int u_levelRow[16];
uniform float u_alpha;
uniform int u_count;
uniform ivec2 u_outputSize;
out vec4 o_value;

vec3 atlasLevel(int level, vec2 uv)
{
    int l = clamp(level, 0, u_levels - 1);
    return mapBilinear(u_atlas, ivec2(0, u_levelRow[l]), max(u_mapSize >> l, ivec2(1)), uv);
}

vec3 atlasLod(float lod, vec2 uv)
{
    float clamped = clamp(lod, 0.0, float(u_levels - 1));
    int low = int(floor(clamped));
    return mix(atlasLevel(low, uv), atlasLevel(low + 1, uv), clamped - float(low));
}

void main()
{
    vec2 uv = gl_FragCoord.xy / vec2(u_outputSize);
    vec3 d = equirectDirection(uv);
    float a = max(u_alpha, 1e-4);
    float s = 0.5 / (a * a);
    float texel = 4.0 * PI / float(u_mapSize.x * u_mapSize.y);  // level 0's mean solid angle
    // a lobe narrower than a texel of the map: the map itself
    if (1.0 / s < texel)
    {
        o_value = vec4(atlasLevel(0, uv), 1.0);
        return;
    }
    vec3 t1 = normalize(cross(abs(d.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), d));
    vec3 t2 = cross(d, t1);
    float tail = exp(-2.0 * s);
    vec3 total = vec3(0.0);
    for (int k = 0; k < u_count; ++k)
    {
        float x1 = (float(k) + 0.5) / float(u_count), x2 = float(vanDerCorput(uint(k))) * 2.3283064365386963e-10;
        float q = x1 + (1.0 - x1) * tail;  // exp(s (cos - 1)) of the sample
        float cosine = clamp(1.0 + log(q) / s, -1.0, 1.0);
        float sine = sqrt(max(1.0 - cosine * cosine, 0.0));
        float phi = 2.0 * PI * x2;
        vec3 w = sine * cos(phi) * t1 + sine * sin(phi) * t2 + cosine * d;
        float pdf = s * q / (2.0 * PI * (1.0 - tail));
        float lod = 0.5 * log2(1.0 / (float(u_count) * pdf) / texel) - 0.5;
        total += atlasLod(lod, equirectUV(w));
    }
    o_value = vec4(total / float(u_count), 1.0);
}

//! display
// The canvas: u_view 0 the gallery (Schlick, basis, basis + MS, reference side by side), 1 one picture, 2 the split
// (left half u_main, right half u_compare), 3 |u_main - u_compare| (linear, the largest channel), 4 their ΔE2000.
uniform sampler2D u_schlick, u_basis, u_multiple, u_sum;
uniform int u_view, u_main, u_compare;
uniform float u_differenceScale;  // the heat map's top: linear difference or ΔE
out vec4 o_color;

vec3 picture(int which, ivec2 pixel)
{
    if (which == 0) return texelFetch(u_schlick, pixel, 0).rgb;
    if (which == 1) return texelFetch(u_basis, pixel, 0).rgb;
    if (which == 2) return texelFetch(u_multiple, pixel, 0).rgb;
    vec4 sum = texelFetch(u_sum, pixel, 0);
    return (sum.a > 0.0) ? sum.rgb / sum.a : vec3(0.0);
}

vec3 srgbEncode(vec3 linear)
{
    linear = clamp(linear, 0.0, 1.0);
    return mix(12.92 * linear, 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055, greaterThan(linear, vec3(0.0031308)));
}

// A perceptual heat ramp: black, purple, orange, yellow-white (displayed as it is, not tone mapped).
vec3 heat(float x)
{
    x = clamp(x, 0.0, 1.0);
    vec3 c = vec3(0.0);
    c = mix(vec3(0.0), vec3(0.34, 0.06, 0.45), smoothstep(0.0, 0.33, x));
    c = mix(c, vec3(0.93, 0.36, 0.13), smoothstep(0.33, 0.7, x));
    return mix(c, vec3(0.99, 0.98, 0.75), smoothstep(0.7, 1.0, x));
}

void main()
{
    int size = int(u_size);
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int which = u_main;
    if (u_view == 0)
    {
        which = pixel.x / size;
        pixel.x -= which * size;
    }
    else if (u_view == 2)
    {
        which = (pixel.x < size / 2) ? u_main : u_compare;
        if (pixel.x == size / 2)
        {
            o_color = vec4(1.0);
            return;
        }
    }
    vec3 shown;
    vec2 q = (vec2(pixel) + 0.5) / u_size * 2.0 - 1.0;
    bool inside = dot(q, q) < 1.0;
    if (u_view >= 3)
    {
        vec3 a = picture(u_main, pixel), b = picture(u_compare, pixel);
        float difference = (u_view == 3) ? max(max(abs(a.r - b.r), abs(a.g - b.g)), abs(a.b - b.b)) : deltaEOfPictures(a, b);
        shown = inside ? heat(difference / u_differenceScale) : vec3(0.0);
    }
    else
    {
        shown = srgbEncode(toneMap(picture(which, pixel)));
    }
    o_color = vec4(shown, 1.0);
}

//! statistics
// ΔE2000 of each split-sum mode against the reference, per pixel (R Schlick, G basis, B basis + MS, A = 1 inside
// the sphere); view.js reads it back for the max and the mean.
uniform sampler2D u_schlick, u_basis, u_multiple, u_sum;
out vec4 o_value;

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec2 q = (vec2(pixel) + 0.5) / u_size * 2.0 - 1.0;
    vec4 sum = texelFetch(u_sum, pixel, 0);
    if (dot(q, q) >= 1.0 || sum.a <= 0.0)
    {
        o_value = vec4(0.0);
        return;
    }
    vec3 reference = sum.rgb / sum.a;
    o_value = vec4(deltaEOfPictures(texelFetch(u_schlick, pixel, 0).rgb, reference),
                   deltaEOfPictures(texelFetch(u_basis, pixel, 0).rgb, reference),
                   deltaEOfPictures(texelFetch(u_multiple, pixel, 0).rgb, reference), 1.0);
}
