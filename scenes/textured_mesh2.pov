// A textured mesh2 two ways: the same declared object (texture_list with
// colours blended across each face, a uv-mapped checker on some faces, uvs,
// normals) as native mesh2 and through subdivision_mesh.
//
// Left:   the mesh2 itself: smooth shading, faceted silhouette.
// Middle: subdivision_mesh { Textured max_level 0 }: the base mesh, the same
//         picture as the left one (the integration tests check it pixel for
//         pixel).
// Right:  subdivision_mesh { Textured }, refined per ray to a pixel: the
//         colours stay where mesh2 puts them (blended by the position on
//         each base triangle) on the smooth surface.
//
//   povray +Itextured_mesh2.pov +W720 +H240 -D
//
// Needs the patched POV-Ray (povray_patch/). See scenes/README.md.
#version 3.7;
global_settings { assumed_gamma 1.0 }

camera { location <0, 1.2, -7.5> look_at <0, 0, 0> right x*image_width/image_height angle 50 }
light_source { <6, 10, -8> rgb 1 }
light_source { <-8, 4, -4> rgb 0.35 shadowless }
background { rgb <0.12, 0.14, 0.2> }
plane { y, -1.05 pigment { checker rgb 0.75 rgb 0.45 } finish { reflection 0.15 } }

#declare Phi = (1 + sqrt(5)) / 2;
#declare Shine = finish { specular 0.5 roughness 0.01 }

// Unit icosahedron: vertex normals are the vertices themselves.
#declare Textured = mesh2 {
  vertex_vectors { 12,
    <-1, Phi, 0>, <1, Phi, 0>, <-1, -Phi, 0>, <1, -Phi, 0>,
    <0, -1, Phi>, <0, 1, Phi>, <0, -1, -Phi>, <0, 1, -Phi>,
    <Phi, 0, -1>, <Phi, 0, 1>, <-Phi, 0, -1>, <-Phi, 0, 1> }
  normal_vectors { 12,
    <-1, Phi, 0>, <1, Phi, 0>, <-1, -Phi, 0>, <1, -Phi, 0>,
    <0, -1, Phi>, <0, 1, Phi>, <0, -1, -Phi>, <0, 1, -Phi>,
    <Phi, 0, -1>, <Phi, 0, 1>, <-Phi, 0, -1>, <-Phi, 0, 1> }
  // Longitude and latitude of each vertex, for the checker.
  uv_vectors { 12,
    <0.6, 0.18>, <0.9, 0.18>, <0.6, 0.82>, <0.9, 0.82>,
    <0.25, 0.66>, <0.25, 0.34>, <0.75, 0.66>, <0.75, 0.34>,
    <0.0, 0.5>, <0.1, 0.5>, <0.5, 0.5>, <0.4, 0.5> }
  texture_list { 4,
    texture { pigment { rgb <0.95, 0.35, 0.15> } finish { Shine } },
    texture { pigment { rgb <0.25, 0.8, 0.35> } finish { Shine } },
    texture { pigment { rgb <0.2, 0.35, 0.95> } finish { Shine } },
    texture { uv_mapping pigment { checker rgb 0.95 rgb 0.15 scale 0.05 } finish { Shine } } }
  // Three indices: a colour per corner, blended over the face (mesh2's
  // colour triangles). One index: the uv-mapped checker.
  face_indices { 20,
    <0, 11, 5>, 0, 2, 2,  <0, 5, 1>, 0, 2, 1,   <0, 1, 7>, 0, 1, 1,
    <0, 7, 10>, 0, 1, 1,  <0, 10, 11>, 0, 1, 2, <1, 5, 9>, 3,
    <5, 11, 4>, 2, 2, 1,  <11, 10, 2>, 2, 1, 2, <10, 7, 6>, 1, 1, 0,
    <7, 1, 8>, 1, 1, 2,   <3, 9, 4>, 3,         <3, 4, 2>, 0, 1, 2,
    <3, 2, 6>, 0, 2, 0,   <3, 6, 8>, 0, 0, 2,   <3, 8, 9>, 0, 2, 0,
    <4, 9, 5>, 3,         <2, 4, 11>, 2, 1, 2,  <6, 2, 10>, 0, 2, 1,
    <8, 6, 7>, 2, 0, 1,   <9, 8, 1>, 0, 2, 1 }
}

// vertices at radius sqrt(1 + Phi^2) = 1.902
#declare Size = 1 / sqrt(1 + Phi * Phi);

object { Textured rotate <15, 25, 0> scale Size translate x * -2.4 }

subdivision_mesh { Textured max_level 0 rotate <15, 25, 0> scale Size }

subdivision_mesh {
  Textured
  scheme normal
  tolerance 1
  max_level 10
  rotate <15, 25, 0> scale Size translate x * 2.4
}
