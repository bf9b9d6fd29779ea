// Lambert key light and headlight, hemisphere fill and a Blinn-Phong
// highlight; shared by the part pass and the mesh pass. Linear RGB in and out.
vec3 lightSurface(ShadeParams s, vec3 albedo, vec3 n, vec3 toViewer)
{
    const float hemi = 0.5 + 0.5 * n.z;
    vec3 c = albedo * mix(s.ground.rgb, s.sky.rgb, hemi);
    c += albedo * s.light.w * max(dot(n, s.light.xyz), 0.0);
    c += albedo * s.view.w * max(dot(n, toViewer), 0.0);
    const vec3 h = normalize(s.light.xyz + toViewer);
    c += vec3(s.sky.w) * pow(max(dot(n, h), 0.0), s.ground.w) * step(0.0, dot(n, s.light.xyz));
    return c;
}

vec3 toSrgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
