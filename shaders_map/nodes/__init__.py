"""One module per node family; importing them fills the registries."""

from . import bsdf, shader, texture, vector, color, converter, inputs  # noqa: F401
