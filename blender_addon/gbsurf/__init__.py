"""GB Surface: converts polygon meshes into smooth surfaces of n-sided Generalized Bezier patches.

This module only registers; the work is in `operators` (Convert, Update), `props` (settings stored
on the result object), `ui` (menu entry and Object properties panel), `handlers` (live mode),
`offset_ops` (exact offsets of surfaces and curves),
`native` (ctypes loader of libgbsurf) and `mesh_io` (numpy transfer of mesh data).
"""

from . import handlers, offset_ops, operators, props, ui

_modules = (props, operators, offset_ops, ui, handlers)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
