// Twenty separate subdivision_mesh objects (issue 16's scene-budget table):
// data/bunny_lowpoly.obj (2,996 triangles) twenty times, each about 1/8 of
// the frame's width, in a 5 x 4 grid. They read one file with the same
// settings, so they share one surface as copies would (docs/povray.md,
// "Memory"). Declare Separate=1 to make them twenty surfaces, as twenty
// different meshes would be: each object's tolerance then differs from the
// next by a relative 1e-12, which changes no refinement visibly but makes
// the settings differ.
// Render from the project root:
//   povray +Iscenes/twenty_bunnies.pov +W640 +H480 -D +WT2 +L<pov include dir>
// Declare Budget=M on the command line to set subdivision_cache_mb, and
// Tolerance=T to set the objects' tolerance (1 by default), and
// Mesh2=1 to draw the uniform level-3 mesh2 from bunny_l3.inc instead
// (`subdivtrace export-mesh2 data/bunny_lowpoly.obj -o bunny_l3.inc --levels 3 --name Bunny_L3`).
#version 3.7;
global_settings {
  assumed_gamma 1.0
  #ifdef (Budget) subdivision_cache_mb Budget #end
}
camera { location <0, 13, -19> look_at <0, -0.5, -0.5> right x*4/3 angle 55 }
light_source { <10, 20, -15> rgb 1 }
light_source { <-12, 8, -6> rgb 0.35 shadowless }
background { rgb <0.15, 0.18, 0.25> }
plane { y, -1.2 pigment { checker rgb 0.8 rgb 0.5 scale 2 } }
#ifdef (Mesh2) #include "bunny_l3.inc" #end
#ifndef (Tolerance) #declare Tolerance = 1; #end

#declare K = 0;
#while (K < 20)
  #declare Place = <-8 + 4 * mod(K, 5), 0, -4.5 + 3 * div(K, 5)>;
  #declare Look = texture {
    pigment { rgb <0.5 + 0.02 * K, 0.6, 0.9 - 0.03 * K> }
    finish { specular 0.4 roughness 0.02 }
  }
  #ifdef (Mesh2)
    object { Bunny_L3 texture { Look } rotate y * (25 * K) translate Place }
  #else
    #ifdef (Separate) #declare Own = Tolerance * (1 + 1e-12 * K); #else #declare Own = Tolerance; #end
    subdivision_mesh { file "data/bunny_lowpoly.obj" max_level 8 tolerance Own
                       texture { Look } rotate y * (25 * K) translate Place }
  #end
  #declare K = K + 1;
#end
