// Unpolarised Fresnel reflectance entering a medium of relative index eta
// (docs/physics.md §3); 1 under total internal reflection.
float fresnel_r(float eta, float c) {
    c = clamp(c, 0.0, 1.0);
    float g2 = eta * eta - 1.0 + c * c;
    if (g2 < 0.0 || c <= 0.0) return 1.0;
    float g = sqrt(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return min(1.0, 0.5 * a * a * (1.0 + b * b));
}
