env { { map base.tga rgbGen const ( 0.2 0.4 0.6 ) alphaGen const 0.5 }
 { map env.tga tcGen environment blendFunc GL_SRC_ALPHA GL_ONE tcMod transform 1 0.5 0 1 0.25 0 }
 { map x.tga tcGen vector ( 0.01 0 0 ) ( 0 0.01 0 ) tcMod stretch triangle 1 .1 0 .5 detail }
 { videoMap intro.roq rgbGen oneMinusEntity alphaGen oneMinusVertex tcMod entityTranslate } }
