leaf { cull none deformVertexes wave 100 sin 3 5 0.1 0.5 deformVertexes move 0 0 4 sin 0 1 0 .2
 { clampMap leaf.tga alphaFunc GE128 depthWrite rgbGen vertex alphaGen lightingSpecular }
 { map $lightmap blendFunc filter depthFunc equal tcGen lightmap } }
