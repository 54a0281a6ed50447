// A texel value as the shaders read it: NaN -> fallback (tested by its bits: fast-math compilers may drop x != x),
// everything else clamped to [lo, hi].
float fresnelSanitize(float x, float fallback, float lo, float hi)
{
    return ((floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u) ? fallback : clamp(x, lo, hi);
}

// The switch between the per-pixel paths (the fresnel...Selected functions): false (the default) reads the per-pixel
// tables of `fresnel-lut build --pixel-tables`, true solves per pixel (a software rasteriser, which filters textures
// in software; a build without those tables). GLSL and HLSL: #define FRESNEL_BASIS_SOLVE true before the include;
// WGSL: the pipeline-overridable constant FRESNEL_BASIS_SOLVE. Either way the compiler keeps one path.
#ifndef FRESNEL_BASIS_SOLVE
#define FRESNEL_BASIS_SOLVE false
#endif

// x clamped to [lo, hi] (0 <= lo < hi) in one integer clamp of its bits, which orders non-negative floats as
// integers: NaN goes to hi or lo by its sign bit, -0 and negatives to lo, +inf to hi. Cheaper than fresnelSanitize
// where the fallback may be an end of the range.
float fresnelBitsClamp(float x, float lo, float hi)
{
    return intBitsToFloat(clamp(floatBitsToInt(x), floatBitsToInt(lo), floatBitsToInt(hi)));
}

float fresnelUnitClamp(float x, float hi)
{
    return fresnelBitsClamp(x, 0.0, hi);
}

// Exact unpolarised Fresnel reflectance of eta + i kappa at mu = cos(theta) (Hoffman 2020, "1823: Fresnel's
// Equations"), written as basis/fresnel.py writes it: finite at mu = 0 and for kappa >> eta.
float fresnelExact(float mu, float eta, float kappa)
{
    float mu2 = mu * mu;
    float sin2 = (1.0 - mu) * (1.0 + mu);
    bool nearOne = abs(eta - 1.0) < 0.5;
    float t = (nearOne ? (eta - 1.0) * (eta + 1.0) : eta * eta) - kappa * kappa + (nearOne ? mu2 : -sin2);
    float fourEta2Kappa2 = 4.0 * (eta * kappa) * (eta * kappa);
    float s = sqrt(t * t + fourEta2Kappa2);  // a^2 + b^2
    float u = s + abs(t);
    float twoA2 = (t >= 0.0) ? u : ((u > 0.0) ? fourEta2Kappa2 / u : 0.0);
    float twoAMu = 2.0 * mu * sqrt(0.5 * twoA2);  // 2 a mu
    float fsDen = s + mu2 + twoAMu;
    float fs = (fsDen > 0.0) ? (s + mu2 - twoAMu) / fsDen : ((eta == 1.0 && kappa == 0.0) ? 0.0 : 1.0);
    float r = s * mu2 + sin2 * sin2;
    float ratioDen = r + twoAMu * sin2;
    float ratio = (ratioDen > 0.0) ? (r - twoAMu * sin2) / ratioDen : 1.0;
    return clamp(0.5 * fs * (1.0 + ratio), 0.0, 1.0);
}

// 2 a^2 = s + t of the exact Fresnel equations without cancellation: u = s + |t| where t >= 0, e4 / u where t < 0
// (e4 = 4 eta^2 kappa^2 = s^2 - t^2); the fit angles' u is positive.
float fresnelTwoA2(float t, float u, float e4)
{
    return (t >= 0.0) ? u : e4 / u;
}
