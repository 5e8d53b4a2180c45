"""A VLM behind an OpenAI-compatible chat-completions endpoint: GPT-class models, or Qwen3-VL
served by vLLM or similar (``models.openai``). Images go as PNG data URLs; the key is read from
the environment variable ``models.openai.api_key_env`` and never stored."""

from __future__ import annotations

import base64
import os

import numpy as np

from rest2art.backends.registry import register
from rest2art.errors import ReconstructionError


def png_data_url(image: np.ndarray) -> str:
    """``data:image/png;base64,...`` of an (H, W, 3) uint8 RGB image."""
    import cv2

    ok, encoded = cv2.imencode(".png", np.ascontiguousarray(image[..., ::-1]))
    return "data:image/png;base64," + base64.b64encode(encoded.tobytes()).decode("ascii")


class ChatClient:
    """``complete(messages) -> str`` over the chat-completions protocol."""

    def __init__(self, config):
        import openai

        self.config = config
        self.where = config.base_url or "the openai client's default endpoint"
        key = os.environ.get(config.api_key_env) or "EMPTY"  # a local server takes any key
        self._client = openai.OpenAI(base_url=config.base_url or None, api_key=key,
                                     timeout=config.timeout_s, max_retries=0)

    def complete(self, messages) -> str:
        import openai

        payload = []
        for m in messages:
            if not m.images:
                payload.append({"role": m.role, "content": m.text})
                continue
            parts = [{"type": "image_url", "image_url": {"url": png_data_url(i)}} for i in m.images]
            payload.append({"role": m.role, "content": [*parts, {"type": "text", "text": m.text}]})
        try:
            reply = self._client.chat.completions.create(model=self.config.model, messages=payload,
                                                         temperature=self.config.temperature,
                                                         max_tokens=self.config.max_tokens)
        except openai.APITimeoutError:
            raise ReconstructionError(f"VLM {self.config.model} at {self.where}: no answer within "
                                      f"{self.config.timeout_s} s (models.openai.timeout_s)") from None
        except openai.APIConnectionError as exc:
            raise ReconstructionError(f"VLM {self.config.model} at {self.where}: cannot connect ({exc})") from None
        except openai.APIStatusError as exc:
            raise ReconstructionError(f"VLM {self.config.model} at {self.where}: HTTP {exc.status_code} "
                                      f"({exc.message})") from None
        if not reply.choices:
            raise ReconstructionError(f"VLM {self.config.model} at {self.where}: an answer without choices")
        return reply.choices[0].message.content or ""


@register("hierarchy", "openai", "a VLM over an OpenAI-compatible chat API (models.openai)",
          packages=("openai",), extra="vlm")
def make_openai_hierarchy(views, face_piece, masks, segment, models):
    from rest2art.backends.vlm import VLMHierarchy

    config = models.openai
    return VLMHierarchy(ChatClient(config), f"openai:{config.model}", config.views, config.image_size)


@register("prompt", "openai", "the motion video's prompt written by a VLM over the chat API (models.openai)",
          packages=("openai",), extra="vlm")
def make_openai_prompt(models):
    from rest2art.backends.vlm import resize_square, video_prompt
    from rest2art.joints.video.source import PROMPT_SUFFIX

    client = ChatClient(models.openai)
    return lambda image, semantics: video_prompt(client, resize_square(image, models.openai.image_size), PROMPT_SUFFIX)
