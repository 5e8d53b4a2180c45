"""SAM3 through transformers (``Sam3Model``): a text prompt per category gives instance masks
and scores (paper: Part Segmentation, ``models.sam3``).

The image is resized and normalised here as the checkpoint's ``preprocessor_config.json`` says
(transformers' own ``Sam3ImageProcessor`` needs torchvision, which the CPU build of torch does
not pair with), the prompt is tokenised by the checkpoint's tokenizer, and the detections are
kept as transformers keeps them: score = sigmoid(logit) x sigmoid(presence), masks upsampled to
the view and thresholded.

Point prompts (the cross-view check) select, among the text-prompted instances of the view,
the one that holds most of the points, as the geometric backend does.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from rest2art.backends.registry import register, require_path, resolve_device, torch_dtype


class Sam3Masks:
    """The masks role over SAM3 for a list of rendered views (instances cached per view and prompt)."""

    def __init__(self, views, config):
        import torch
        from transformers import AutoTokenizer, Sam3Model

        self.views = views
        self.config = config
        path = require_path(config.path, "models.sam3.path", "SAM3 model folder (facebook/sam3)")
        self.device = resolve_device(config.device)
        self.dtype = torch_dtype(config.dtype, self.device)
        self.model = Sam3Model.from_pretrained(path, dtype=self.dtype).to(self.device).eval()
        self.tokenizer = AutoTokenizer.from_pretrained(path)
        pre = Path(path) / "preprocessor_config.json"
        settings = json.loads(pre.read_text()) if pre.is_file() else {}
        size = settings.get("size", {})
        self.size = (int(size.get("height", config.image_size)), int(size.get("width", config.image_size)))
        self.mean = np.asarray(settings.get("image_mean", [0.5, 0.5, 0.5]), np.float32)
        self.std = np.asarray(settings.get("image_std", [0.5, 0.5, 0.5]), np.float32)
        self._torch = torch
        self._cache: dict[tuple[int, str], list] = {}

    def pixel_values(self, image: np.ndarray):
        """(1, 3, h, w) normalised tensor of an (H, W, 3) uint8 image at the model's size."""
        import cv2

        resized = cv2.resize(image, (self.size[1], self.size[0]), interpolation=cv2.INTER_LINEAR)
        x = (resized.astype(np.float32) / 255.0 - self.mean) / self.std
        return self._torch.from_numpy(x.transpose(2, 0, 1)[None].copy()).to(self.device, self.dtype)

    def detect(self, image: np.ndarray, prompt: str) -> tuple[np.ndarray, np.ndarray]:
        """(K, H, W) bool masks and (K,) scores of the instances of ``prompt`` in ``image``."""
        torch = self._torch
        text = self.tokenizer([prompt], padding="max_length", max_length=32, truncation=True, return_tensors="pt")
        with torch.no_grad():
            out = self.model(pixel_values=self.pixel_values(image), input_ids=text["input_ids"].to(self.device),
                             attention_mask=text["attention_mask"].to(self.device))
        scores = out.pred_logits.float().sigmoid()[0]
        if getattr(out, "presence_logits", None) is not None:
            scores = scores * out.presence_logits.float().sigmoid()[0]
        keep = scores > self.config.score_threshold
        if not bool(keep.any()):
            return np.zeros((0, *image.shape[:2]), bool), np.zeros(0)
        masks = out.pred_masks.float()[0][keep].sigmoid()[None]
        masks = torch.nn.functional.interpolate(masks, size=image.shape[:2], mode="bilinear", align_corners=False)[0]
        return (masks > self.config.mask_threshold).cpu().numpy(), scores[keep].cpu().numpy()

    def segment(self, view: int, category: str) -> list:
        from rest2art.parts.segment.roles import InstanceMask

        key = (view, category)
        if key not in self._cache:
            masks, scores = self.detect(self.views[view].shaded(), category)
            self._cache[key] = [InstanceMask(view, category, m, float(s)) for m, s in zip(masks, scores) if m.any()]
        return self._cache[key]

    def segment_points(self, view: int, category: str, pixels: np.ndarray):
        """The instance holding most of the (N, 2) integer pixel prompts (x, y), or None when
        none holds half of them."""
        from rest2art.parts.segment.roles import instance_at_points

        return instance_at_points(self.segment(view, category), pixels)


@register("masks", "sam3", "SAM3 through transformers, a text prompt per category (models.sam3)",
          packages=("torch", "transformers"), extra="sam3",
          weights=lambda models: {"SAM3 model folder": models.sam3.path},
          hints={"SAM3 model folder": "download facebook/sam3 (Hugging Face, gated) and set models.sam3.path"})
def make_sam3_masks(views, face_piece, segment, models):
    return Sam3Masks(views, models.sam3)
