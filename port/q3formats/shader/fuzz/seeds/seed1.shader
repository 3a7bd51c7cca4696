sky1 { surfaceparm sky surfaceparm noimpact q3map_sun 1 .9 .8 120 45 60 q3map_sunExt 1 1 1 100 30 40 2 16
 skyparms env/sky 512 - { map clouds.tga tcMod scale 3 2 tcMod scroll 0.01 0.02 tcMod turb 0 .1 0 .2 } }
