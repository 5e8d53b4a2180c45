"""What the VLM backends share: the paper's prompts, the part tree as JSON, and the hierarchy
role over any chat client.

A client is any object with ``complete(messages) -> str`` where ``messages`` is a list of
``Message`` (role, text, images); the chat-API and the local Qwen3-VL backends differ only
there.

The tree comes back as one JSON object with the single root key ``base``; every key below it
names a part (``door_0``, ``drawer``, ``handle_1`` ...) and maps to its own children (an object,
a list of names or objects, or nothing). The category of a part is its name without the index.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field

import numpy as np

from rest2art.errors import ReconstructionError

TREE_CATEGORIES = ("base", "door", "drawer", "handle", "knob", "lid", "tray")
"""Categories a tree may hold (the paper's set, with lids for boxes and laptops)."""
PANELS = ("door", "drawer", "lid")
MAX_HANDLES_PER_DOOR = 2

SYSTEM_PROMPT = """You recognise the articulated parts of an object shown in an image.

Step 1. Find every articulated part of the object; each belongs to one of these categories: \
base, door, drawer, lid, knob, handle, tray.
- There is exactly one base.
- A tray only exists inside a microwave.
- Every handle is attached to a door, a drawer or a lid.
- A door carries at most two handles.
Telling a door from a drawer: think about where its handle is, the proportions of the panel and \
how it would move. Doors give access to a compartment and swing on a hinge or slide sideways; a \
drawer front belongs to a box that slides straight out. Weigh the geometry, the proportions and \
what the part is for together rather than one fixed rule.

Step 2. Describe how the parts connect and arrange them in a part connectivity tree. The base is \
the root; every other part hangs under the base or under another articulated part.

Answer with a short description followed by one JSON object inside ```json fences, whose only \
root key is "base". Each key names a part with its category and an index (door_0, handle_1) and \
maps to an object of its children, e.g.
```json
{"base": {"door_0": {"handle_0": {}}, "drawer_0": {"handle_1": {}}, "knob_0": {}}}
```"""

REVISE_PROMPT = ("The coloured regions of this image are the parts a segmentation model found in this view "
                 "({detected}). The tree you gave before was:\n```json\n{tree}\n```\nLook at the image again, "
                 "count the parts, and answer with the corrected tree in the same format.")

ASK_PROMPT = "Here is a rendered view of the object. Give its part connectivity tree."

REASK_PROMPT = ("Your answer held no valid tree: {error}. Answer again with only the JSON object inside "
                "```json fences, with the single root key \"base\".")

VIDEO_PROMPT_SYSTEM = """You reason about articulated objects and write prompts for a motion-aware \
video model.
Given one image of an object, write ONE prompt for the WAN2.2 image-to-video model that makes ALL \
articulated parts move at the same time while the camera stays perfectly still.

Requirements:
1. The camera is locked for the whole clip: fixed intrinsics and extrinsics; no pan, tilt, roll, \
zoom or dolly; no stabilisation drift, parallax or reframing.
2. All articulated parts move together: drawers slide out together, doors and panels swing open \
together, handles move only with the part they are attached to. The motions are synchronised, \
smooth, mechanically plausible, of moderate range, consistent with gravity and free of collisions.
3. The object keeps its exact identity and geometry: no part is added, removed or duplicated; \
textures, patterns, background and lighting stay the same in every frame.
4. Photorealistic, soft studio lighting, stable geometry, cinematic clarity.

Do NOT mention segmentation masks, colours or annotations.
Output only the final WAN2.2 prompt."""

VIDEO_PROMPT_ASK = "Write the prompt for this object."


@dataclass
class Message:
    role: str
    """system, user or assistant."""
    text: str
    images: list[np.ndarray] = field(default_factory=list)
    """(H, W, 3) uint8 RGB images shown with the text."""


class TreeError(ValueError):
    """A VLM answer that holds no valid part tree."""


def extract_json(text: str) -> object:
    """The JSON object in ``text``: the last ```json fenced block, else the outermost braces."""
    fenced = re.findall(r"```(?:json)?\s*(.*?)```", text, flags=re.S)
    candidates = [b for b in fenced if "{" in b] or [text[text.find("{"): text.rfind("}") + 1]]
    try:
        return json.loads(candidates[-1])
    except (json.JSONDecodeError, IndexError) as exc:
        raise TreeError(f"not valid JSON ({exc})") from None


def category_of(name: str) -> str:
    """``door_0`` -> ``door``; ``Drawer 2`` -> ``drawer``; plural ``doors`` -> ``door``."""
    base = re.sub(r"[\s_\-]*\d+$", "", name.strip().lower())
    return base[:-1] if base.endswith("s") and base[:-1] in TREE_CATEGORIES else base


def parse_tree(data: object):
    """The ``PartTree`` of a decoded JSON answer; a TreeError says what breaks the schema."""
    from rest2art.parts.segment.roles import PartNode, PartTree

    if not isinstance(data, dict) or list(data) != ["base"]:
        keys = list(data) if isinstance(data, dict) else type(data).__name__
        raise TreeError(f"the object must have exactly one root key 'base', got {keys}")
    nodes = [PartNode("base", "base", None)]
    seen: dict[str, int] = {}

    def children(value: object) -> list[tuple[str, object]]:
        if value is None:
            return []
        if isinstance(value, dict):
            return list(value.items())
        if isinstance(value, str):
            return [(value, None)]
        if isinstance(value, list):
            return [pair for item in value for pair in children(item)]
        raise TreeError(f"children must be an object, a list or a name, got {value!r}")

    def walk(parent: str, value: object) -> None:
        for key, sub in children(value):
            category = category_of(str(key))
            if category not in TREE_CATEGORIES or category == "base":
                raise TreeError(f"part '{key}' is not one of {', '.join(TREE_CATEGORIES[1:])}")
            name = f"{category}_{seen.get(category, 0)}"
            seen[category] = seen.get(category, 0) + 1
            nodes.append(PartNode(name, category, parent))
            walk(name, sub)

    walk("base", data["base"])
    category = {n.name: n.category for n in nodes}
    for node in nodes:
        if node.category == "handle" and category.get(node.parent) not in PANELS:
            raise TreeError(f"{node.name} hangs under {node.parent}; a handle belongs to a door, drawer or lid")
    for node in nodes:
        if node.category == "door":
            handles = sum(1 for n in nodes if n.parent == node.name and n.category == "handle")
            if handles > MAX_HANDLES_PER_DOOR:
                raise TreeError(f"{node.name} has {handles} handles; a door has at most {MAX_HANDLES_PER_DOOR}")
    return PartTree(nodes)


def tree_json(tree) -> str:
    """The tree in the answer format (``{"base": {"door_0": {...}}}``)."""
    def below(name: str) -> dict:
        return {n.name: below(n.name) for n in tree.nodes if n.parent == name}

    return json.dumps({"base": below("base")})


def ask_tree(client, image: np.ndarray, text: str, log: list[dict], view: int):
    """Ask ``client`` for a tree about ``image``; one re-ask when the answer is invalid. Returns
    the PartTree, or None when both answers were invalid (the reason goes to ``log``)."""
    messages = [Message("system", SYSTEM_PROMPT), Message("user", text, [image])]
    for attempt in range(2):
        answer = client.complete(messages)
        try:
            tree = parse_tree(extract_json(answer))
            log.append({"view": view, "attempt": attempt, "parts": len(tree.nodes) - 1})
            return tree
        except TreeError as exc:
            log.append({"view": view, "attempt": attempt, "invalid": str(exc)})
            messages += [Message("assistant", answer), Message("user", REASK_PROMPT.format(error=exc))]
    return None


def pick_views(n_views: int, wanted: int) -> list[int]:
    """``wanted`` view indices spread evenly over ``n_views`` (all when ``wanted`` >= n_views)."""
    if wanted >= n_views:
        return list(range(n_views))
    return sorted({int(round(k)) for k in np.linspace(0, n_views - 1, max(wanted, 1))})


def resize_square(image: np.ndarray, size: int) -> np.ndarray:
    """(size, size, 3) uint8 copy of ``image`` (area-resampled)."""
    import cv2

    if image.shape[:2] == (size, size):
        return image
    return cv2.resize(image, (size, size), interpolation=cv2.INTER_AREA)


class VLMHierarchy:
    """The hierarchy role over a VLM client (paper: Hierarchy Tree Construction).

    ``propose`` asks about each of ``views`` rendered views and keeps the tree with most parts;
    ``revise`` shows the mask overlay of a view whose detections exceed the tree, with the tree
    so far, and takes the corrected tree (the tree stands when the answer is invalid)."""

    def __init__(self, client, name: str, views: int, image_size: int):
        self.client = client
        self.name = name
        self.views = views
        self.image_size = image_size
        self.log: list[dict] = []

    def propose(self, views: list) -> "object":
        trees = []
        for v in pick_views(len(views), self.views):
            tree = ask_tree(self.client, resize_square(views[v].shaded(), self.image_size), ASK_PROMPT, self.log, v)
            if tree is not None:
                trees.append(tree)
        if not trees:
            raise ReconstructionError(f"hierarchy backend '{self.name}': no valid part tree in any answer "
                                      f"({self.log[-1].get('invalid', 'no answer')})")
        return max(trees, key=lambda t: len(t.nodes))

    def revise(self, views: list, tree, view: int, overlay: np.ndarray, detected: dict[str, int]):
        counts = ", ".join(f"{n} {c}" for c, n in sorted(detected.items())) or "nothing"
        text = REVISE_PROMPT.format(detected=counts, tree=tree_json(tree))
        revised = ask_tree(self.client, resize_square(overlay, self.image_size), text, self.log, view)
        return tree if revised is None else revised


def video_prompt(client, image: np.ndarray, suffix: str) -> str:
    """The motion video's prompt written by ``client`` from the (H, W, 3) overlay ``image``,
    with ``suffix`` (the camera lock) appended."""
    answer = client.complete([Message("system", VIDEO_PROMPT_SYSTEM), Message("user", VIDEO_PROMPT_ASK, [image])])
    text = " ".join(answer.strip().strip('"').split())
    return f"{text} {suffix}" if suffix not in text else text
