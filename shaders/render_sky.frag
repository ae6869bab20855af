// The environment behind everything: the camera ray's sky colour, alpha 0 (no geometry).
#include "render_params.glsl"

out vec4 fragColor;

void main() { fragColor = vec4(renderSky(renderRayDirection(gl_FragCoord.xy)), 0.0); }
