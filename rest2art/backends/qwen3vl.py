"""Qwen3-VL run locally through transformers (``Qwen3VLForConditionalGeneration`` and the
checkpoint's processor, ``models.qwen3vl``): the hierarchy role with the same prompts and
checks as the chat-API backend, and the writer of the motion video's prompt (the paper's
choice for it)."""

from __future__ import annotations

from rest2art.backends.registry import register, require_path, resolve_device, torch_dtype


class Qwen3VLClient:
    """``complete(messages) -> str`` through a local Qwen3-VL."""

    def __init__(self, config):
        from transformers import AutoProcessor, Qwen3VLForConditionalGeneration

        self.config = config
        path = require_path(config.path, "models.qwen3vl.path", "Qwen3-VL model folder")
        self.device = resolve_device(config.device)
        self.model = Qwen3VLForConditionalGeneration.from_pretrained(
            path, dtype=torch_dtype(config.dtype, self.device)).to(self.device).eval()
        self.processor = AutoProcessor.from_pretrained(path)

    def complete(self, messages) -> str:
        import torch
        from PIL import Image

        conversation = [{"role": m.role, "content": [*({"type": "image", "image": Image.fromarray(i)} for i in m.images),
                                                      {"type": "text", "text": m.text}]} for m in messages]
        inputs = self.processor.apply_chat_template(conversation, tokenize=True, add_generation_prompt=True,
                                                    return_dict=True, return_tensors="pt").to(self.device)
        sample = self.config.temperature > 0
        with torch.no_grad():
            out = self.model.generate(**inputs, max_new_tokens=self.config.max_new_tokens, do_sample=sample,
                                      **({"temperature": self.config.temperature} if sample else {}))
        answer = out[:, inputs["input_ids"].shape[1]:]
        return self.processor.batch_decode(answer, skip_special_tokens=True)[0]


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
    from rest2art.articulate.video_source import PROMPT_SUFFIX
    from rest2art.backends.vlm import resize_square, video_prompt

    client = Qwen3VLClient(models.qwen3vl)
    return lambda image, semantics: video_prompt(client, resize_square(image, models.qwen3vl.image_size), PROMPT_SUFFIX)
