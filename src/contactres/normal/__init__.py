"""Normal contact: isotropic Hertz/JKR/DMT (``isotropic``) and anisotropic Hertz (``anisotropic``).

The public functions of both modules are re-exported here and from :mod:`contactres`.
"""
