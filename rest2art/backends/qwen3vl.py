"""Qwen3-VL run locally through transformers (``Qwen3VLForConditionalGeneration`` with the
checkpoint's tokenizer, image processor and chat template, ``models.qwen3vl``): the hierarchy
role with the same prompts and checks as the chat-API backend, and the writer of the motion
video's prompt (the paper's choice for it)."""

from __future__ import annotations

from rest2art.backends.registry import register, require_path, resolve_device, torch_dtype
from rest2art.errors import ConfigError

IMAGE_TOKEN = "<|image_pad|>"
"""The placeholder a Qwen-VL chat template writes once per image."""


def expand_image_tokens(text: str, grids: list[list[int]], merge_size: int) -> str:
    """``text`` with its k-th ``IMAGE_TOKEN`` repeated once per merged patch of image k.

    ``grids``: (N, 3) patches per image along time, height and width (the image processor's
    ``image_grid_thw``); ``merge_size``: patches merged per side into one token."""
    pieces = text.split(IMAGE_TOKEN)
    counts = [t * h * w // merge_size**2 for t, h, w in grids]
    return pieces[0] + "".join(IMAGE_TOKEN * n + piece for n, piece in zip(counts, pieces[1:]))


class Qwen3VLClient:
    """``complete(messages) -> str`` through a local Qwen3-VL.

    The inputs are built as the checkpoint's processor builds them for images (each image's
    placeholder expanded per merged patch, image tokens marked in ``mm_token_type_ids`` for the
    multimodal rotary positions). The processor class is not loaded: it also loads the video
    processor, which needs torchvision and is never used here."""

    def __init__(self, config):
        from transformers import AutoImageProcessor, AutoTokenizer, Qwen3VLForConditionalGeneration, Qwen3VLProcessor

        self.config = config
        path = require_path(config.path, "models.qwen3vl.path", "Qwen3-VL model folder")
        self.device = resolve_device(config.device)
        self.model = Qwen3VLForConditionalGeneration.from_pretrained(
            path, dtype=torch_dtype(config.dtype, self.device)).to(self.device).eval()
        self.tokenizer = AutoTokenizer.from_pretrained(path)
        self.image_processor = AutoImageProcessor.from_pretrained(path)
        template = Qwen3VLProcessor.get_processor_dict(path)[0].get("chat_template") or self.tokenizer.chat_template
        if not isinstance(template, str):
            raise ConfigError(f"models.qwen3vl.path: {path} holds no chat template "
                              "(chat_template.jinja or chat_template.json, as the checkpoint ships them)")
        self.chat_template = template

    def encode(self, messages) -> dict:
        """The model's inputs for ``messages``: input_ids, attention_mask, mm_token_type_ids
        (1, L) and, with images, pixel_values and image_grid_thw."""
        from PIL import Image

        conversation = [{"role": m.role, "content": [*({"type": "image"} for _ in m.images),
                                                      {"type": "text", "text": m.text}]} for m in messages]
        text = self.tokenizer.apply_chat_template(conversation, chat_template=self.chat_template, tokenize=False,
                                                  add_generation_prompt=True)
        images = [Image.fromarray(i) for m in messages for i in m.images]
        if text.count(IMAGE_TOKEN) != len(images):
            raise ConfigError(f"models.qwen3vl.path: the chat template of {self.config.path} writes "
                              f"{text.count(IMAGE_TOKEN)} image placeholders ({IMAGE_TOKEN}) for {len(images)} images")
        pixels = dict(self.image_processor(images=images, return_tensors="pt")) if images else {}
        grids = pixels["image_grid_thw"].tolist() if images else []
        text = expand_image_tokens(text, grids, self.image_processor.merge_size)
        # the template already writes every special token
        tokens = dict(self.tokenizer(text, add_special_tokens=False, return_token_type_ids=False, return_tensors="pt"))
        image_id = self.tokenizer.convert_tokens_to_ids(IMAGE_TOKEN)
        tokens["mm_token_type_ids"] = (tokens["input_ids"] == image_id).long()
        return {k: v.to(self.device) for k, v in {**tokens, **pixels}.items()}

    def complete(self, messages) -> str:
        import torch

        inputs = self.encode(messages)
        sample = self.config.temperature > 0
        with torch.no_grad():
            out = self.model.generate(**inputs, max_new_tokens=self.config.max_new_tokens, do_sample=sample,
                                      **({"temperature": self.config.temperature} if sample else {}))
        answer = out[:, inputs["input_ids"].shape[1]:]
        return self.tokenizer.batch_decode(answer, skip_special_tokens=True)[0]


_WEIGHTS = {"weights": lambda models: {"Qwen3-VL model folder": models.qwen3vl.path},
            "hints": {"Qwen3-VL model folder": "download Qwen/Qwen3-VL-8B-Instruct (or another size) and set "
                                               "models.qwen3vl.path"}}


@register("hierarchy", "qwen3vl", "Qwen3-VL through transformers (models.qwen3vl)",
          packages=("torch", "transformers"), extra="vlm", **_WEIGHTS)
def make_qwen3vl_hierarchy(views, face_piece, masks, segment, models):
    from rest2art.backends.vlm import VLMHierarchy

    config = models.qwen3vl
    return VLMHierarchy(Qwen3VLClient(config), "qwen3vl", config.views, config.image_size)


@register("prompt", "qwen3vl", "the motion video's prompt written by Qwen3-VL through transformers (models.qwen3vl)",
          packages=("torch", "transformers"), extra="vlm", **_WEIGHTS)
def make_qwen3vl_prompt(models):
    from rest2art.backends.vlm import resize_square, video_prompt
    from rest2art.joints.video.source import PROMPT_SUFFIX

    client = Qwen3VLClient(models.qwen3vl)
    return lambda image, semantics: video_prompt(client, resize_square(image, models.qwen3vl.image_size), PROMPT_SUFFIX)
