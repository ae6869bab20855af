// Triangle meshes (water, colliders, ground, tank walls): world position and normal to the fragment.
#include "render_params.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;

uniform mat4 uModel;  // translation only (keyframed colliders), so normals need no inverse transpose

out vec3 vWorld;
out vec3 vNormal;

void main() {
  vec4 world = uModel * vec4(inPosition, 1.0);
  vWorld = world.xyz;
  vNormal = mat3(uModel) * inNormal;
  gl_Position = renderViewProj * world;
}
