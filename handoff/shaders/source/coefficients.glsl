// Coefficients of (eta, kappa^2), already in range, whose F(0) is f0: c0 = f0, c1 = F(90) - c0, then the constant
// inverse of the fit angles (Belcour, Bati, Barla 2020, "Coefficients").
{{terms}} fresnelCoefficientsSolve(float f0, float eta, float kappa2)
{
    float f90 = (eta == 1.0 && kappa2 == 0.0) ? 0.0 : 1.0;
{{solve}}
}

// The same with F(0) in closed form.
{{terms}} fresnelCoefficientsEtaKappa2(float eta, float kappa2)
{
    float f0 = ((eta - 1.0) * (eta - 1.0) + kappa2) / ((eta + 1.0) * (eta + 1.0) + kappa2);
    return fresnelCoefficientsSolve(f0, eta, kappa2);
}

// Coefficients of one channel's (eta, kappa).
{{terms}} fresnelCoefficientsNK(float eta, float kappa)
{
    kappa = fresnelSanitize(kappa, 0.0, 0.0, 1e4);
    return fresnelCoefficientsEtaKappa2(fresnelSanitize(eta, 1.5, 1e-4, 1e4), kappa * kappa);
}

// Gulbrandsen's (r, g) -> (eta, kappa^2) (JCGT 2014, eq. 7-9) for r in [0, 0.9999], g in [0, 1], with q = sqrt(r):
// kappa^2 = (r (n + 1)^2 - (n - 1)^2) / (1 - r) factored exactly into g (n_max - n_min)(n - 1/n_max)
// = 4 g r / ((1 + r)(1 - q)) (g (1 - q) / (1 + r) + 2 (1 - g) / (1 - q)), a product and a sum of positive terms (no
// float32 cancellation). n_max = (1 + q) / (1 - q) keeps n - 1 to a few ulps as r -> 0.
vec2 fresnelGulbrandsenToEtaKappa2(float r, float g)
{
    float q = sqrt(r);
    float over1pr = 1.0 / (1.0 + r);
    float over1mq = 1.0 / (1.0 - q);
    float n = g * (1.0 - r) * over1pr + (1.0 - g) * (1.0 + q) * over1mq;
    return vec2(n, 4.0 * g * r * over1pr * over1mq * (g * (1.0 - q) * over1pr + 2.0 * (1.0 - g) * over1mq));
}

// Gulbrandsen's F(0) is r itself: no closed-form F(0) needed.
{{terms}} fresnelCoefficientsGulbrandsen(float r, float g)
{
    r = fresnelSanitize(r, 0.0, 0.0, 0.9999);
    vec2 nk2 = fresnelGulbrandsenToEtaKappa2(r, fresnelSanitize(g, 0.0, 0.0, 1.0));
    return fresnelCoefficientsSolve(r, nk2.x, nk2.y);
}

// Gulbrandsen's (r, g) with one fetch of the coefficient table instead of the solve (fresnel_coefficients_rgb,
// written by `fresnel-lut build --pixel-tables` from this include's basis): c0 = r, c1 = f90 - r with f90 the
// table's last channel (1, and 0 in the column of r = 0, which a clamped read returns alone), c2 ... from the others,
// bilinear on the warped axes x = r^(1/4) - sqrt(1 - r)/2 and s = (1 - g)^(1/4) (rows at y = 1 - s, folded into
// FRESNEL_COEFFICIENT_AXES); every coefficient 0 at r = 0. The table holds one weighted least-squares fit over theta
// (basis.coefficient_table), where the solve interpolates four angles.
// fresnelCoefficientsTableRead takes r in [0, 0.9999], q = sqrt(r) and g in [0, 1].
{{terms}} fresnelCoefficientsTableRead(sampler2D coefficientLut, float r, float q, float g)
{
    float x = sqrt(q) - 0.5 * sqrt(1.0 - r);
    float s = sqrt(sqrt(1.0 - g));
    vec4 t = textureLod(coefficientLut, vec2(x, s) * FRESNEL_COEFFICIENT_AXES.xz + FRESNEL_COEFFICIENT_AXES.yw, 0.0);
    return {{table_terms}};
}

// Inputs through fresnelUnitClamp: r to [0, 0.9999], g to [0, 1], a NaN to an end by its sign bit.
{{terms}} fresnelCoefficientsGulbrandsenTable(sampler2D coefficientLut, float r, float g)
{
    r = fresnelUnitClamp(r, 0.9999);
    return fresnelCoefficientsTableRead(coefficientLut, r, sqrt(r), fresnelUnitClamp(g, 1.0));
}

// (eta, kappa) through the same table: Gulbrandsen's r = F(0) in closed form and his g = (n_max - eta) /
// (n_max - n_min) (JCGT 2014, the inverse of eq. 7-9), written as (1 + q - eta (1 - q)) (1 + r) / (2 q (1 + q)),
// q = sqrt(r), which n_max - n_min = 2 q (1 + q) / ((1 - q)(1 + r)) keeps free of float32 cancellation; g clamped to
// [0, 1], so a material outside Gulbrandsen's gamut (eta < n_min) reads as its nearest edge. Inputs through
// fresnelBitsClamp: eta to [1e-4, 1e4], kappa to [0, 1e4], a NaN to an end by its sign bit.
{{terms}} fresnelCoefficientsNKTable(sampler2D coefficientLut, float eta, float kappa)
{
    eta = fresnelBitsClamp(eta, 1e-4, 1e4);
    kappa = fresnelUnitClamp(kappa, 1e4);
    float kappa2 = kappa * kappa;
    float r = min(((eta - 1.0) * (eta - 1.0) + kappa2) / ((eta + 1.0) * (eta + 1.0) + kappa2), 0.9999);
    float q = sqrt(r);
    float g = q > 0.0 ? (1.0 + q - eta * (1.0 - q)) * (1.0 + r) / (2.0 * q * (1.0 + q)) : 0.0;
    return fresnelCoefficientsTableRead(coefficientLut, r, q, clamp(g, 0.0, 1.0));
}

// Gulbrandsen's (r, g) and (eta, kappa) by the path FRESNEL_BASIS_SOLVE selects.
{{terms}} fresnelCoefficientsGulbrandsenSelected(sampler2D coefficientLut, float r, float g)
{
    if (FRESNEL_BASIS_SOLVE)
    {
        return fresnelCoefficientsGulbrandsen(r, g);
    }
    return fresnelCoefficientsGulbrandsenTable(coefficientLut, r, g);
}

{{terms}} fresnelCoefficientsNKSelected(sampler2D coefficientLut, float eta, float kappa)
{
    if (FRESNEL_BASIS_SOLVE)
    {
        return fresnelCoefficientsNK(eta, kappa);
    }
    return fresnelCoefficientsNKTable(coefficientLut, eta, kappa);
}

// Linear artist models: F = w0 (1 - (1 - mu)^5) + w1 (1 - mu)^5 + w2 mu (1 - mu)^6 (Hoffman 2023, eq. 5-6 with p = 5).
// fresnelLinear<Model> gives one channel's weights w = (w0, w1, w2), its inputs sanitised to [0, 1] (NaN to 0): the
// Schlick table's R, G and A preintegrate the three functions exactly (fresnelLinearSplitSum), and
// fresnelCoefficients<Model> projects the same weights onto the basis.

// Schlick 1994 with F90 (F90 = 1: the usual Schlick).
vec3 fresnelLinearSchlick(float f0, float f90)
{
    return vec3(fresnelSanitize(f0, 0.0, 0.0, 1.0), fresnelSanitize(f90, 0.0, 0.0, 1.0), 0.0);
}

// Hoffman 2019's absolute reflectance at arccos(1/7) (eq. 4).
vec3 fresnelLinearF82(float f0, float f82)
{
    f0 = fresnelSanitize(f0, 0.0, 0.0, 1.0);
    f82 = fresnelSanitize(f82, 0.0, 0.0, 1.0);
    return vec3(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT - f82) / FRESNEL_F82_DIP);
}

// Adobe's F82 tint (OpenPBR specular_color, MaterialX color82; Hoffman 2023 eq. 3): a tint on Schlick at arccos(1/7).
vec3 fresnelLinearF82Tint(float f0, float tint)
{
    f0 = fresnelSanitize(f0, 0.0, 0.0, 1.0);
    tint = fresnelSanitize(tint, 0.0, 0.0, 1.0);
    return vec3(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}

// Hoffman 2023's generalised Adobe model, eq. 6, with p = 5.
vec3 fresnelLinearGeneralizedAdobe(float r0, float r90, float tint)
{
    r0 = fresnelSanitize(r0, 0.0, 0.0, 1.0);
    r90 = fresnelSanitize(r90, 0.0, 0.0, 1.0);
    tint = fresnelSanitize(tint, 0.0, 0.0, 1.0);
    return vec3(r0, r90, -(r0 + (r90 - r0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}

// The basis coefficients of a linear model's weights: c = w0 P_scale + w1 P_bias + w2 P_dip (the projections of its
// fixed functions).
{{terms}} fresnelCoefficientsLinear(vec3 w)
{
{{linear}}
}

{{terms}} fresnelCoefficientsSchlick(float f0, float f90)
{
    return fresnelCoefficientsLinear(fresnelLinearSchlick(f0, f90));
}

{{terms}} fresnelCoefficientsF82(float f0, float f82)
{
    return fresnelCoefficientsLinear(fresnelLinearF82(f0, f82));
}

{{terms}} fresnelCoefficientsF82Tint(float f0, float tint)
{
    return fresnelCoefficientsLinear(fresnelLinearF82Tint(f0, tint));
}

{{terms}} fresnelCoefficientsGeneralizedAdobe(float r0, float r90, float tint)
{
    return fresnelCoefficientsLinear(fresnelLinearGeneralizedAdobe(r0, r90, tint));
}

// All three channels at once, for (eta, kappa) and (r, g) texture reads.
void fresnelCoefficientsNK3(vec3 eta, vec3 kappa, out {{terms}} cR, out {{terms}} cG, out {{terms}} cB)
{
    cR = fresnelCoefficientsNK(eta.x, kappa.x);
    cG = fresnelCoefficientsNK(eta.y, kappa.y);
    cB = fresnelCoefficientsNK(eta.z, kappa.z);
}

void fresnelCoefficientsGulbrandsen3(vec3 r, vec3 g, out {{terms}} cR, out {{terms}} cG, out {{terms}} cB)
{
    cR = fresnelCoefficientsGulbrandsen(r.x, g.x);
    cG = fresnelCoefficientsGulbrandsen(r.y, g.y);
    cB = fresnelCoefficientsGulbrandsen(r.z, g.z);
}

void fresnelCoefficientsGulbrandsenTable3(sampler2D coefficientLut, vec3 r, vec3 g, out {{terms}} cR, out {{terms}} cG, out {{terms}} cB)
{
    cR = fresnelCoefficientsGulbrandsenTable(coefficientLut, r.x, g.x);
    cG = fresnelCoefficientsGulbrandsenTable(coefficientLut, r.y, g.y);
    cB = fresnelCoefficientsGulbrandsenTable(coefficientLut, r.z, g.z);
}
