"""facetool: intrinsic face decomposition of photos (albedo, normals, SH visibility, SH light).

    import facetool
    photo = facetool.decompose(image)        # (H, W, 3) uint8 sRGB or float linear RGB, or a path
    for face in photo.faces:
        face.albedo, face.normal, face.visibility, face.light   # crop frame, (S, S, C) / (3, 9)
        face.landmarks, face.coverage                           # photo frame
    photo.albedo, photo.normal                                  # (H, W, C) pasted back
    relit = facetool.relight(photo, facetool.light_from_dpr([...]))

See docs/python.md. Computation releases the GIL; one Model runs one call at a time.
"""

import os as _os

# Installed by pip, the shipped model lies in the package (facetool/models); the build tree's and the
# system install's are found from libfacetool_core's folder.
_package_models = _os.path.join(_os.path.dirname(__file__), "models")
if not _os.environ.get("FACETOOL_MODEL_DIR") and _os.path.isdir(_package_models):
    _os.environ["FACETOOL_MODEL_DIR"] = _package_models

from ._facetool import (  # noqa: E402,F401
    Error,
    Face,
    Model,
    Photo,
    backends,
    default_model_path,
    light_from_direction,
    light_from_dpr,
    light_from_sfsnet,
    light_to_dpr,
    light_to_sfsnet,
    read_image,
    read_light,
)

__all__ = [
    "Error", "Face", "Model", "Photo", "backends", "decompose", "default_model_path", "light_from_direction", "light_from_dpr",
    "light_from_sfsnet", "light_to_dpr", "light_to_sfsnet", "load_model", "read_image", "read_light", "relight", "view",
]

_models = {}


def load_model(weights=None, backend="cpu", renderer="sh_renderer", landmark_model=None, mirror_average=True,
               landmark_normals=True, light_gain=True, light_solve=True):
    """Loads a decomposition model (a facetool.Model).

    weights: a .safetensors file (None: the shipped model, facetool-v2). backend: one of
    facetool.backends() ("cpu", "opencl", ...). renderer: the renderer plugin. landmark_model:
    dlib's 68-point shape predictor (None: Debian libdlib-data's; research use only).
    mirror_average: run each face crop beside its mirror image and average the two answers, as the
    facetool program does (False: one network pass per face, half the network's time).
    landmark_normals: blend the normals of the weights' landmark normal head, if they carry one (the
    shipped model does), into the network's, as the facetool program does (False: the network's
    normals alone, as its --no-landmark-normals, which also leaves the light's gain out).
    light_gain: scale each colour of the network's light to render the face best in the landmark
    normal head's face mask, as the facetool program does (False: the network's light as it is, as
    its --no-light-gain).
    light_solve: solve each face's light from its shading (a distant light plus ambient, then its colour, that
    makes the renderer explain the face's pixels), the albedo following from the photo and that
    shading, as the facetool program does (False: the network's light, as its --no-light-solve).
    """
    if weights is not None:
        weights = _os.fspath(weights)
        if not weights:
            raise ValueError("weights: an empty path; give a .safetensors file, or None for the shipped model")
    else:
        weights = _shipped_model()
    return Model(weights, backend=backend, renderer=renderer, landmark_model=landmark_model,
                 mirror_average=mirror_average, landmark_normals=landmark_normals, light_gain=light_gain,
                 light_solve=light_solve)


def _shipped_model():
    """The shipped model's path: where facetool finds it ($FACETOOL_MODEL_DIR, then beside the
    library), else the copy packaged with this module (a FACETOOL_MODEL_DIR that lacks it must not
    hide it); facetool.Error naming both places when neither has it."""
    try:
        return default_model_path()
    except Error as e:
        packaged = _os.path.join(_package_models, "facetool-v2.safetensors")
        if _os.path.isfile(packaged):
            return packaged
        raise Error(f"{e} (nor in the module's own folder {_package_models})") from None


def _default_model(backend):
    if backend not in _models:
        _models[backend] = load_model(backend=backend)
    return _models[backend]


def decompose(image, model=None, backend="cpu", **options):
    """Decomposes every face of a photo; returns a facetool.Photo.

    image: (H, W, 3) numpy array (uint8: sRGB; float32/float64: linear RGB) or a file path.
    model: a facetool.Model (None: the shipped model on `backend`, loaded once).
    options: max_faces, min_face_size, min_score, face_region ("auto", "hull" or "forehead"), feather, batch,
    layers (the photo-level layers to compute, e.g. ["normal"]; None: every one) (see Model.decompose).
    Raises facetool.Error when no face is found, TypeError/ValueError for an unusable array.
    """
    model = model if model is not None else _default_model(backend)
    if isinstance(image, str):
        return model.decompose_file(image, **options)
    return model.decompose(image, **options)


def relight(photo, light, model=None, backend="cpu", **options):
    """Relights a decomposed photo with `light` ((3, 9) SH in the photo frame); returns (H, W, 3).

    model: the facetool.Model that decomposed it (None: the default model on `backend`).
    options: mode ("ratio" or "render"), visibility (False: no self-shadowing), ratio_epsilon.
    """
    model = model if model is not None else _default_model(backend)
    return model.relight(photo, light, **options)


def view(photo, path):
    """Writes the view page of `photo` (a facetool.Photo) to `path`: the self-contained HTML page that
    `facetool view` writes for infer's folder of the same photo (docs/viewer.md)."""
    if not isinstance(photo, Photo):
        raise TypeError(f"view: photo must be a facetool.Photo (from decompose()), not {type(photo).__name__}")
    photo.write_view(_os.fspath(path))


def _photo_repr_html(photo):
    # Jupyter shows a Photo as its view page, inline: an iframe whose srcdoc holds the whole page
    # (no file, no server; the page's own Content-Security-Policy still applies).
    import html as _html
    page = photo.view_html().decode("utf-8")
    return ('<iframe style="width: 100%; height: 900px; border: 0" sandbox="allow-scripts allow-downloads" '
            f'srcdoc="{_html.escape(page, quote=True)}"></iframe>')


Photo._repr_html_ = _photo_repr_html
