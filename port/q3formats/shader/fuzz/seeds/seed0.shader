textures/a/wall
{
	qer_editorimage textures/a/wall.tga
	surfaceparm nomarks
	{
		map $lightmap
		rgbGen identity
	}
	{
		map textures/a/wall.tga
		blendFunc GL_DST_COLOR GL_ZERO
	}
}
