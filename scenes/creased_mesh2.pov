// A textured, creased mesh2 two ways: a 12-sided cylinder whose side corners
// carry radial normals and whose cap corners carry the axis (so both rims are
// creases), with colours blended across the sides (texture_list, three
// indices per face) and one texture per cap face.
//
// Left:   the mesh2 itself: smooth shading on a 12-sided silhouette.
// Middle: subdivision_mesh { Creased max_level 0 }: the base mesh, the same
//         picture (the integration tests check it pixel for pixel).
// Right:  subdivision_mesh { Creased }, refined per ray to a pixel: round
//         sides, flat caps, and rims that stay sharp at every level.
//
//   povray +Icreased_mesh2.pov +W720 +H240 -D
//
// Needs the patched POV-Ray (povray_patch/). See scenes/README.md.
// Written by hand from a 12-step loop (vertex i at angle 30 i degrees).
#version 3.7;
global_settings { assumed_gamma 1.0 }

camera { location <0, 2.6, -7.5> look_at <0, -0.1, 0> right x*image_width/image_height angle 50 }
light_source { <6, 10, -8> rgb 1 }
light_source { <-8, 4, -4> rgb 0.35 shadowless }
background { rgb <0.12, 0.14, 0.2> }
plane { y, -0.75 pigment { checker rgb 0.75 rgb 0.45 } finish { reflection 0.15 } }

#declare Shine = finish { specular 0.5 roughness 0.01 }

#declare Creased = mesh2 {
  vertex_vectors { 26,
    <1, -0.6, 0>, <0.866025404, -0.6, 0.5>, <0.5, -0.6, 0.866025404>, <6.123234e-17, -0.6, 1>,
    <-0.5, -0.6, 0.866025404>, <-0.866025404, -0.6, 0.5>, <-1, -0.6, 1.2246468e-16>, <-0.866025404, -0.6, -0.5>,
    <-0.5, -0.6, -0.866025404>, <-1.8369702e-16, -0.6, -1>, <0.5, -0.6, -0.866025404>, <0.866025404, -0.6, -0.5>,
    <1, 0.6, 0>, <0.866025404, 0.6, 0.5>, <0.5, 0.6, 0.866025404>, <6.123234e-17, 0.6, 1>,
    <-0.5, 0.6, 0.866025404>, <-0.866025404, 0.6, 0.5>, <-1, 0.6, 1.2246468e-16>, <-0.866025404, 0.6, -0.5>,
    <-0.5, 0.6, -0.866025404>, <-1.8369702e-16, 0.6, -1>, <0.5, 0.6, -0.866025404>, <0.866025404, 0.6, -0.5>,
    <0, -0.6, 0>, <0, 0.6, 0> }
  normal_vectors { 14,
    <1, 0, 0>, <0.866025404, 0, 0.5>, <0.5, 0, 0.866025404>, <6.123234e-17, 0, 1>,
    <-0.5, 0, 0.866025404>, <-0.866025404, 0, 0.5>, <-1, 0, 1.2246468e-16>, <-0.866025404, 0, -0.5>,
    <-0.5, 0, -0.866025404>, <-1.8369702e-16, 0, -1>, <0.5, 0, -0.866025404>, <0.866025404, 0, -0.5>,
    <0, -1, 0>, <0, 1, 0> }
  texture_list { 4,
    texture { pigment { rgb <0.95, 0.35, 0.15> } finish { Shine } },
    texture { pigment { rgb <0.25, 0.8, 0.35> } finish { Shine } },
    texture { pigment { rgb <0.2, 0.35, 0.95> } finish { Shine } },
    texture { pigment { rgb <0.85, 0.85, 0.8> } finish { Shine } } }
  // Sides: a colour per corner, blended across the face. Caps: one texture.
  face_indices { 48,
    <0, 13, 1>, 0, 1, 1, <0, 12, 13>, 0, 0, 1, <24, 0, 1>, 3, <25, 13, 12>, 3,
    <1, 14, 2>, 1, 2, 2, <1, 13, 14>, 1, 1, 2, <24, 1, 2>, 3, <25, 14, 13>, 3,
    <2, 15, 3>, 2, 0, 0, <2, 14, 15>, 2, 2, 0, <24, 2, 3>, 3, <25, 15, 14>, 3,
    <3, 16, 4>, 0, 1, 1, <3, 15, 16>, 0, 0, 1, <24, 3, 4>, 3, <25, 16, 15>, 3,
    <4, 17, 5>, 1, 2, 2, <4, 16, 17>, 1, 1, 2, <24, 4, 5>, 3, <25, 17, 16>, 3,
    <5, 18, 6>, 2, 0, 0, <5, 17, 18>, 2, 2, 0, <24, 5, 6>, 3, <25, 18, 17>, 3,
    <6, 19, 7>, 0, 1, 1, <6, 18, 19>, 0, 0, 1, <24, 6, 7>, 3, <25, 19, 18>, 3,
    <7, 20, 8>, 1, 2, 2, <7, 19, 20>, 1, 1, 2, <24, 7, 8>, 3, <25, 20, 19>, 3,
    <8, 21, 9>, 2, 0, 0, <8, 20, 21>, 2, 2, 0, <24, 8, 9>, 3, <25, 21, 20>, 3,
    <9, 22, 10>, 0, 1, 1, <9, 21, 22>, 0, 0, 1, <24, 9, 10>, 3, <25, 22, 21>, 3,
    <10, 23, 11>, 1, 2, 2, <10, 22, 23>, 1, 1, 2, <24, 10, 11>, 3, <25, 23, 22>, 3,
    <11, 12, 0>, 2, 0, 0, <11, 23, 12>, 2, 2, 0, <24, 11, 0>, 3, <25, 12, 23>, 3 }
  // Side corners take their radial normal, cap corners the axis: the two
  // rims are creases.
  normal_indices { 48,
    <0, 1, 1>, <0, 0, 1>, <12, 12, 12>, <13, 13, 13>, <1, 2, 2>, <1, 1, 2>,
    <12, 12, 12>, <13, 13, 13>, <2, 3, 3>, <2, 2, 3>, <12, 12, 12>, <13, 13, 13>,
    <3, 4, 4>, <3, 3, 4>, <12, 12, 12>, <13, 13, 13>, <4, 5, 5>, <4, 4, 5>,
    <12, 12, 12>, <13, 13, 13>, <5, 6, 6>, <5, 5, 6>, <12, 12, 12>, <13, 13, 13>,
    <6, 7, 7>, <6, 6, 7>, <12, 12, 12>, <13, 13, 13>, <7, 8, 8>, <7, 7, 8>,
    <12, 12, 12>, <13, 13, 13>, <8, 9, 9>, <8, 8, 9>, <12, 12, 12>, <13, 13, 13>,
    <9, 10, 10>, <9, 9, 10>, <12, 12, 12>, <13, 13, 13>, <10, 11, 11>, <10, 10, 11>,
    <12, 12, 12>, <13, 13, 13>, <11, 0, 0>, <11, 11, 0>, <12, 12, 12>, <13, 13, 13> }
}

object { Creased rotate <-15, 10, 0> translate x * -2.4 }

subdivision_mesh { Creased max_level 0 rotate <-15, 10, 0> }

subdivision_mesh {
  Creased
  scheme normal
  tolerance 1
  max_level 10
  rotate <-15, 10, 0> translate x * 2.4
}
