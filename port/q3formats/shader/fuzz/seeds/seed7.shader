"quoted name" { { map "a b.tga" blendFunc blend alphaFunc LT128 rgbGen exactVertex } }
