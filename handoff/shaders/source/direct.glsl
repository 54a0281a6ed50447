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
