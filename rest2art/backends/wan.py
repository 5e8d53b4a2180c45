"""Wan2.2 image-to-video through diffusers (``WanImageToVideoPipeline``) as the motion video
role (paper: Articulation Video Synthesis, ``models.wan``).

The pipeline folder is a diffusers export (Wan2.2-I2V-A14B-Diffusers: two transformers for the
high- and low-noise phases, no image encoder). LoRA files (the paper's VBVR and step
distillation adapters) are loaded into every transformer at ``lora_scale``. Frames come out at
``size`` x ``size`` and are resized to the conditioning image.
"""

from __future__ import annotations

import numpy as np

from rest2art.backends.registry import register, require_path, resolve_device, torch_dtype


class WanVideo:
    """``generate(image, prompt, seed, n_frames) -> (T, H, W, 3) uint8``."""

    def __init__(self, config):
        from diffusers import WanImageToVideoPipeline

        self.config = config
        path = require_path(config.path, "models.wan.path", "Wan2.2 I2V diffusers folder")
        self.device = resolve_device(config.device)
        dtype = torch_dtype(config.dtype, self.device)
        self.pipe = WanImageToVideoPipeline.from_pretrained(path, torch_dtype=dtype)
        names = []
        for k, lora in enumerate(config.lora_paths):
            lora = require_path(lora, f"models.wan.lora_paths[{k}]", "LoRA file")
            name = f"lora_{k}"
            self.pipe.load_lora_weights(lora, adapter_name=name)
            if getattr(self.pipe, "transformer_2", None) is not None:
                self.pipe.load_lora_weights(lora, adapter_name=name, load_into_transformer_2=True)
            names.append(name)
        if names:
            self.pipe.set_adapters(names, [config.lora_scale] * len(names))
        if config.cpu_offload:
            self.pipe.enable_model_cpu_offload(device=self.device)
        else:
            self.pipe.to(self.device)
        self.pipe.set_progress_bar_config(disable=True)

    def generate(self, image: np.ndarray, prompt: str, seed: int, n_frames: int) -> np.ndarray:
        """Frames animating the (H, W, 3) uint8 ``image`` as ``prompt`` says; ``n_frames`` is
        rounded up to the model's 4k + 1."""
        import cv2
        import torch
        from PIL import Image

        size = self.config.size
        frames = 4 * int(np.ceil((max(n_frames, 5) - 1) / 4)) + 1
        generator = torch.Generator(device="cpu").manual_seed(int(seed))
        out = self.pipe(image=Image.fromarray(image).resize((size, size), Image.BICUBIC), prompt=prompt,
                        negative_prompt=self.config.negative_prompt or None, height=size, width=size,
                        num_frames=frames, num_inference_steps=self.config.steps,
                        guidance_scale=self.config.guidance_scale, generator=generator, output_type="np").frames[0]
        video = (np.clip(np.asarray(out, np.float32), 0.0, 1.0) * 255).round().astype(np.uint8)
        h, w = image.shape[:2]
        return np.stack([cv2.resize(f, (w, h), interpolation=cv2.INTER_AREA) for f in video])


@register("video", "wan2.2", "Wan2.2 image-to-video through diffusers, with LoRAs (models.wan)",
          packages=("torch", "diffusers", "transformers", "ftfy"), extra="video",
          weights=lambda models: {"Wan2.2 pipeline folder": models.wan.path,
                                  **{f"LoRA {k}": p for k, p in enumerate(models.wan.lora_paths)}},
          hints={"Wan2.2 pipeline folder": "download Wan-AI/Wan2.2-I2V-A14B-Diffusers and set models.wan.path"})
def make_wan(models):
    return WanVideo(models.wan)
