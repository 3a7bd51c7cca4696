fog { surfaceparm fog surfaceparm trans fogparms ( .5 .2 .1 ) 300 sort underwater polygonOffset portal }
mirror { portal sort portal { map $whiteimage blendFunc GL_ONE GL_ONE_MINUS_SRC_ALPHA alphaGen portal 256 } }
