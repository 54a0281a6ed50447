// The curves b_0 .. b_(K-1) at mu = V.H: b_0 = 1, the others polynomials in the warped cosine x (Horner).
{{terms}} fresnelBasisCurves(float mu)
{
    mu = fresnelSanitize(mu, 1.0, 0.0, 1.0);
{{curves}}
}

// Fresnel of a punctual light for each colour channel: F(V.H) = sum_k c_k b_k(theta_h).
vec3 fresnelBasisDirect(float VdotH, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    {{terms}} b = fresnelBasisCurves(VdotH);
    return vec3(fresnelTermsDot(cR, b), fresnelTermsDot(cG, b), fresnelTermsDot(cB, b));
}

// The same from the curve table (fresnel_curves_rgb, `fresnel-lut build --pixel-tables`): b_1 .. b_(K-1) at
// FRESNEL_CURVE_TABLE's end points of mu = V.H, one bilinear fetch in place of the polynomial; V.H through
// fresnelUnitClamp. A basis of more than five terms has no such table and evaluates the polynomial.
vec3 fresnelBasisDirectTable(sampler2D curveLut, float VdotH, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    float mu = fresnelUnitClamp(VdotH, 1.0);
    vec4 t = textureLod(curveLut, vec2(mu * FRESNEL_CURVE_TABLE.x + FRESNEL_CURVE_TABLE.y, FRESNEL_CURVE_TABLE.z), 0.0);
    {{terms}} b = {{curve_terms}};
    return vec3(fresnelTermsDot(cR, b), fresnelTermsDot(cG, b), fresnelTermsDot(cB, b));
}

// F(V.H) by the path FRESNEL_BASIS_SOLVE selects: the polynomial (true) or the curve table.
vec3 fresnelBasisDirectSelected(sampler2D curveLut, float VdotH, {{terms}} cR, {{terms}} cG, {{terms}} cB)
{
    if (FRESNEL_BASIS_SOLVE)
    {
        return fresnelBasisDirect(VdotH, cR, cG, cB);
    }
    return fresnelBasisDirectTable(curveLut, VdotH, cR, cG, cB);
}

// A linear model's F(V.H) for a punctual light, per colour channel, in closed form: dot(w, (1 - s, s, mu (1 - mu)^6))
// with s = (1 - mu)^5, clamped to [0, 1] as the models are.
vec3 fresnelLinearDirect(float VdotH, vec3 wR, vec3 wG, vec3 wB)
{
    float mu = fresnelSanitize(VdotH, 1.0, 0.0, 1.0);
    float m = 1.0 - mu;
    float m2 = m * m;
    float s = m2 * m2 * m;
    vec3 t = vec3(1.0 - s, s, mu * s * m);
    return clamp(vec3(dot(wR, t), dot(wG, t), dot(wB, t)), vec3(0.0), vec3(1.0));
}
