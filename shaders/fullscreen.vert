// One triangle that covers the whole viewport (vertices at (-1, -1), (3, -1), (-1, 3)): every pixel gets exactly one
// fragment, at gl_FragCoord = pixel + 0.5. Drawn with glDrawArrays(GL_TRIANGLES, 0, 3) and an empty vertex array.
void main()
{
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
