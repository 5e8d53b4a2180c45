"""Model roles and their backends, behind one registry per role.

The paper drives its pipeline with four pretrained models; each is a *role* here, with an
offline geometric default and model backends that load weights from a local path:

=========  ============================================  =====================================
role       default (offline)                             model backends
=========  ============================================  =====================================
hierarchy  ``geometric`` (rules over rendered panels)    ``openai`` (chat API), ``qwen3vl``
masks      ``geometric`` (panels in rendered maps)       ``sam3``
video      ``none`` (``--motion-video`` folders)         ``wan2.2``
tracks     ``lucas_kanade`` (OpenCV)                     ``cotracker3``
prompt     ``template`` (the motion video's prompt)      ``openai``, ``qwen3vl``
=========  ============================================  =====================================

Each backend is one module of this package that registers itself with ``register``; the
modules import their heavy libraries (torch, transformers, diffusers, openai) only when a
backend is built, so listing and choosing backends costs nothing.
"""

from rest2art.backends.registry import ROLES, Backend, available, create, get, register, resolve_device, torch_dtype

__all__ = ["ROLES", "Backend", "available", "create", "get", "register", "resolve_device", "torch_dtype"]
