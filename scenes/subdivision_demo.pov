// A 2996-triangle organic mesh (data/bunny_lowpoly.obj) three ways:
//
// Left:   native mesh2 of the base mesh (flat triangles).
// Middle: native mesh2 of uniform subdivision, level Uniform_Level (smooth
//         normals; 4^Level times the triangles, all parsed and stored).
// Right:  subdivision_mesh: the same scheme, refined per ray only as far as
//         the pixel needs (tolerance 1 pixel).
//
// The two mesh2 includes are written by the subdivtrace CLI; render_demo.sh
// makes them and renders this scene:
//   scenes/render_demo.sh build          (writes build/scenes/subdivision_demo.png)
// Without them only the subdivision_mesh is drawn.
#version 3.7;
global_settings { assumed_gamma 1.0 }

// Scheme: 0 normal (default), 1 loop, 2 butterfly (render_demo.sh passes Declare=Scheme=N)
#ifndef (Scheme) #declare Scheme = 0; #end

camera { location <0, 1.3, -8.5> look_at <0, 0.1, 0> right x*image_width/image_height angle 48 }
light_source { <6, 10, -8> rgb 1 area_light x*2, y*2, 3, 3 adaptive 1 jitter }
light_source { <-8, 4, -4> rgb 0.3 shadowless }
background { rgb <0.12, 0.14, 0.2> }
plane { y, -0.95 pigment { checker rgb 0.78 rgb 0.5 scale 0.5 } finish { reflection 0.1 } }

#declare Look = texture {
  pigment { rgb <0.85, 0.6, 0.4> }
  finish { specular 0.35 roughness 0.02 }
}

#if (file_exists("bunny_base.inc"))
  #include "bunny_base.inc"
  object { Bunny_Base texture { Look } rotate y*-30 translate x * -2.8 }
#end

#if (file_exists("bunny_uniform.inc"))
  #include "bunny_uniform.inc"
  object { Bunny_Uniform texture { Look } rotate y*-30 }
#end

subdivision_mesh {
  file "../data/bunny_lowpoly.obj"
  #switch (Scheme)
    #case (1) scheme loop #break
    #case (2) scheme butterfly #break
    #else scheme normal
  #end
  tolerance 1
  max_level 8
  cache_mb 256
  texture { Look }
  rotate y*-30 translate x * 2.8
}
