// subdivision_mesh beside native mesh2: the same 20 triangles, inline.
//
// Left:   mesh2 (flat triangles).
// Middle: mesh2 with vertex normals (smooth shading, faceted silhouette).
// Right:  subdivision_mesh, scheme normal: refined per ray until every edge
//         is below one pixel (tolerance 1), so the silhouette is smooth too.
//
//   povray +Iicosahedron_side_by_side.pov +W640 +H240 -D
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
#macro Ico_Vertices()
  vertex_vectors { 12,
    <-1, Phi, 0>, <1, Phi, 0>, <-1, -Phi, 0>, <1, -Phi, 0>,
    <0, -1, Phi>, <0, 1, Phi>, <0, -1, -Phi>, <0, 1, -Phi>,
    <Phi, 0, -1>, <Phi, 0, 1>, <-Phi, 0, -1>, <-Phi, 0, 1> }
#end
#macro Ico_Normals()
  normal_vectors { 12,
    <-1, Phi, 0>, <1, Phi, 0>, <-1, -Phi, 0>, <1, -Phi, 0>,
    <0, -1, Phi>, <0, 1, Phi>, <0, -1, -Phi>, <0, 1, -Phi>,
    <Phi, 0, -1>, <Phi, 0, 1>, <-Phi, 0, -1>, <-Phi, 0, 1> }
#end
#macro Ico_Faces()
  face_indices { 20,
    <0, 11, 5>, <0, 5, 1>, <0, 1, 7>, <0, 7, 10>, <0, 10, 11>,
    <1, 5, 9>, <5, 11, 4>, <11, 10, 2>, <10, 7, 6>, <7, 1, 8>,
    <3, 9, 4>, <3, 4, 2>, <3, 2, 6>, <3, 6, 8>, <3, 8, 9>,
    <4, 9, 5>, <2, 4, 11>, <6, 2, 10>, <8, 6, 7>, <9, 8, 1> }
#end

#declare Look = texture {
  pigment { rgb <0.95, 0.55, 0.2> }
  finish { specular 0.5 roughness 0.01 reflection 0.05 }
}
// vertices at radius sqrt(1 + Phi^2) = 1.902
#declare Size = 1 / sqrt(1 + Phi * Phi);

mesh2 { Ico_Vertices() Ico_Faces()
  texture { Look } rotate <15, 25, 0> scale Size translate x * -2.4 }

mesh2 { Ico_Vertices() Ico_Normals() Ico_Faces()
  texture { Look } rotate <15, 25, 0> scale Size }

subdivision_mesh {
  mesh2 { Ico_Vertices() Ico_Faces() }
  scheme normal
  tolerance 1
  max_level 10
  texture { Look } rotate <15, 25, 0> scale Size translate x * 2.4
}
