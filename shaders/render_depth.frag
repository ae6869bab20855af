// Depth-only pass (water back faces for the thickness estimate): colour writes are masked off.
out vec4 fragColor;

void main() { fragColor = vec4(0.0); }
