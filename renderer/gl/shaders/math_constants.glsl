// Constants shared by the shading parts.
const float PI = 3.14159265358979;
