"""The colour rule from Python (docs/colour.md): colours given to the bindings are display (sRGB)
colours, decoded once as they enter, so an unlit mesh shows them in to_uint8() to 1/255, and
Mesh.colors gives back what was given (to float precision: where the sRGB curve is flatter than
1, neighbouring floats decode to one linear float)."""

import numpy as np

import intermix

# A square facing the camera square on (counter-clockwise seen from -y, where the camera is).
SQUARE = np.array([[-20, 0, -20], [20, 0, -20], [20, 0, 20], [-20, 0, 20]], float)
TRIANGLES = [[0, 1, 2], [0, 2, 3]]
GIVEN = np.array([204, 153, 51])  # bytes, as a colour chooser gives them


def unlit_square(material_color, vertex_colors=None):
    scene = intermix.Scene()
    scene.set("image", {"width": 16, "height": 16})
    scene.set("camera", {"eye": [0, -200, 0], "target": [0, 0, 0], "up": [0, 0, 1],
                         "projection": "orthographic", "ortho_height": 20})
    scene.add_mesh("square", intermix.Mesh(SQUARE, TRIANGLES, colors=vertex_colors),
                   material={"color": list(material_color), "shading": {"enabled": False}})
    return scene.render(method="reference").to_uint8()[8, 8, :3].astype(int)


def test_a_material_colour_shows_as_given():
    assert np.abs(unlit_square(GIVEN / 255.0) - GIVEN).max() <= 1


def test_vertex_colours_show_as_given_and_read_back_the_same():
    colours = np.tile(GIVEN / 255.0, (4, 1)).astype(np.float32)
    mesh = intermix.Mesh(SQUARE, TRIANGLES, colors=colours)
    assert np.abs(mesh.colors - colours).max() <= 1e-6
    assert np.abs(unlit_square([1, 1, 1], colours) - GIVEN).max() <= 1
