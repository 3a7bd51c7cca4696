light { q3map_surfacelight 2500 q3map_lightimage glow.tga q3map_lightRGB 1 0.5 0.2 cull disable
 { animMap 4 a1.tga a2.tga a3.tga blendFunc add rgbGen wave sin 0.5 0.25 0 1 tcMod rotate 30 } }
