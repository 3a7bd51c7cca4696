/* comment */ a // line
{ deformVertexes autosprite2 deformVertexes text3 deformVertexes bulge 3 3 1
 deformVertexes normal 0.5 2 deformVertexes projectionShadow sort 12 nopicmip nomipmaps entityMergable
 tessSize 128 q3map_globaltexture qer_trans 0.5 light 1 }
