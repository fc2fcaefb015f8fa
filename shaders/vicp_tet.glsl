// What VICP's vertex program (vicp_vertex.vert) passes to its fragment program (vicp_fragment.frag), flat: the GLSL
// twin of struct VicpTet in gpu/vicp/vicp_vertex.h, whose comments say what each member is. Compiled in front of both
// stages' files. A flat varying is the provoking vertex's value copied without arithmetic, and every vertex of a
// tetrahedron computes the same constants, so the fragment program sees the vertex program's bits.
struct VicpTet {
    dvec3 p0;       // vertex 0 of the snapped shape, relative to the mesh's centre
    dvec3 m[3];     // gradients of lambda_1, lambda_2, lambda_3 of the snapped shape
    double det;     // e1 . (e2 x e3)
    dvec3 base;     // vertex 0 of the exact cell
    dvec3 me[3];    // gradients of lambda_1..3 of the exact cell
    dvec3 g;        // the normalized scalar's gradient
    double s0;      // normalized scalar at vertex 0
    uint boundary;  // bit i: the face opposite vertex i lies on the mesh's boundary
};
