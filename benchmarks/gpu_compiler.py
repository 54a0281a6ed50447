"""What a GPU's own shader compiler estimates a fragment shader costs, with no GPU at hand.

Mesa's Vulkan driver for AMD GPUs (RADV) opens a GPU that is not there when ``RADV_FORCE_FAMILY`` names one (its
"null winsys", which Mesa's shader-db and Fossilize replays use). Pipelines are then compiled for real by ACO, Mesa's
AMD compiler, to that GPU's instruction set, and VK_KHR_pipeline_executable_properties reports ACO's statistics
(``src/amd/compiler/aco_statistics.cpp``): the instructions, the VGPRs (which set how many waves share a SIMD), a
latency estimate, and the inverse throughput, the cycles per 64 pixels of the busiest unit once the latency of texture
reads is hidden behind the other waves. It is a static model of one GPU, not a timing: it does not see the texture
units' own throughput, caches or bandwidth. What it sees is the arithmetic, which a software rasteriser such as
llvmpipe weighs against its own software texture filtering (a GPU issues a filtered fetch to its texture unit as
one instruction).

Run: ``python -m benchmarks.gpu_compiler SHADER.frag [...] [--family navi21] [--json]`` (GLSL fragment shaders,
``#version 450``; loose uniforms and unbound samplers are accepted and bound in order). The shader-cost benchmark
calls :func:`compiler_estimates`. Needs glslangValidator (Debian glslang-tools), Mesa's RADV (mesa-vulkan-drivers)
and the Python Vulkan binding (the ``gpu`` extra), all of which the test set-up installs.

Public objects: ``compiler_estimates``, ``radv_manifest``, ``FAMILY``, ``STATISTICS``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

__all__ = ["FAMILY", "STATISTICS", "compiler_estimates", "radv_manifest"]

#: The GPU compiled for: AMD RDNA 2 (Radeon RX 6800/6900, the generation of the current consoles' GPUs).
FAMILY = "navi21"
#: ACO's statistics reported, as RADV names them.
STATISTICS = ("Instructions", "VGPRs", "Subgroups per SIMD", "Latency", "Inverse Throughput")
#: Bindings of the compiled shaders: samplers from 0 in order of declaration, loose uniforms in one block here.
_SAMPLERS, _UNIFORM_BLOCK = 16, 16
_VERTEX = "#version 450\nlayout(location = 0) in vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }\n"


def compiler_estimates(fragments: dict[str, str], family: str = FAMILY) -> tuple[dict[str, dict[str, int]], str]:
    """ACO's statistics (:data:`STATISTICS`) of each GLSL fragment shader (``#version 450``), compiled for ``family``,
    and the compiler in words (``RADV NAVI21, Mesa 22.3.6``).

    The compilation runs in a child process: RADV reads ``RADV_FORCE_FAMILY`` when the Vulkan loader starts, and the
    caller's own Vulkan (wgpu on lavapipe, say) stays as it is. Raises ``RuntimeError`` with the child's message where
    a tool is missing or a shader does not compile."""
    with tempfile.TemporaryDirectory() as folder:
        paths = []
        for index, source in enumerate(fragments.values()):
            path = Path(folder) / f"shader{index}.frag"
            path.write_text(source, encoding="utf-8")
            paths.append(str(path))
        environment = dict(
            os.environ,
            RADV_FORCE_FAMILY=family,
            RADV_DEBUG="nocache",
            MESA_SHADER_CACHE_DISABLE="true",
            VK_ICD_FILENAMES=radv_manifest(),
        )
        completed = subprocess.run(
            [sys.executable, "-m", "benchmarks.gpu_compiler", "--compile-here", "--json", "--family", family, *paths],
            capture_output=True,
            text=True,
            env=environment,
            cwd=Path(__file__).resolve().parents[1],
            timeout=600,
        )
    if completed.returncode != 0:
        raise RuntimeError(f"ACO's estimates failed: {completed.stderr.strip()[-2000:]}")
    report = json.loads(completed.stdout)
    return dict(zip(fragments, report["estimates"])), report["compiler"]


def radv_manifest() -> str:
    """The Vulkan loader's manifest of RADV (Debian's mesa-vulkan-drivers), so that no other driver is loaded; raises
    ``RuntimeError`` where RADV is not installed."""
    for folder in ("/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d", "/usr/local/share/vulkan/icd.d"):
        for manifest in sorted(Path(folder).glob("radeon_icd*.json")):
            return str(manifest)
    raise RuntimeError("RADV, Mesa's Vulkan driver for AMD GPUs, is not installed (Debian mesa-vulkan-drivers)")


def _spirv(source: str, stage: str) -> bytes:
    """SPIR-V of one GLSL stage by glslangValidator, loose uniforms gathered into one block (Vulkan's relaxed rules)."""
    validator = shutil.which("glslangValidator")
    if validator is None:
        raise RuntimeError("glslangValidator is not installed (Debian glslang-tools)")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"shader.{stage}"
        path.write_text(source, encoding="utf-8")
        compiled = subprocess.run(
            [validator, "-V", "-R", "--amb", "--aml", "--sdub", "defaultUniforms", "0", str(_UNIFORM_BLOCK)]
            + ["--target-env", "vulkan1.2", str(path), "-o", str(path) + ".spv"],
            capture_output=True,
            text=True,
        )
        if compiled.returncode != 0:
            raise RuntimeError(f"glslangValidator: {compiled.stdout.strip()} {compiled.stderr.strip()}")
        return (Path(folder) / f"shader.{stage}.spv").read_bytes()


def _estimate(fragment_paths: list[str], family: str) -> tuple[list[dict[str, int]], str]:
    """In the child (``RADV_FORCE_FAMILY`` set): one graphics pipeline per fragment shader on RADV's device of
    ``family``, ACO's statistics of its fragment stage; and the device and driver in words."""
    try:
        import vulkan as vk
    except ImportError as error:
        raise RuntimeError("the Python Vulkan binding is not installed (pip install -e '.[gpu]')") from error

    application = vk.VkApplicationInfo(pApplicationName="fresnel-basis", apiVersion=vk.VK_MAKE_VERSION(1, 3, 0))
    instance = vk.vkCreateInstance(vk.VkInstanceCreateInfo(pApplicationInfo=application), None)
    devices = [
        device
        for device in vk.vkEnumeratePhysicalDevices(instance)
        if family.upper() in vk.vkGetPhysicalDeviceProperties(device).deviceName.upper()
    ]
    if not devices:
        raise RuntimeError(f"RADV offers no {family} device (is RADV_FORCE_FAMILY={family} known to this Mesa?)")
    properties = vk.vkGetPhysicalDeviceProperties(devices[0])
    version = properties.driverVersion  # Mesa's own version, in Vulkan's encoding
    compiler = (
        f"{properties.deviceName.replace('Null hardware (', '').rstrip(')')}, Mesa "
        f"{version >> 22}.{(version >> 12) & 0x3FF}.{version & 0xFFF}"
    )
    features = vk.VkPhysicalDeviceDynamicRenderingFeatures(
        pNext=vk.VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR(pipelineExecutableInfo=vk.VK_TRUE),
        dynamicRendering=vk.VK_TRUE,
    )
    queue = vk.VkDeviceQueueCreateInfo(queueFamilyIndex=0, queueCount=1, pQueuePriorities=[1.0])
    device = vk.vkCreateDevice(
        devices[0],
        vk.VkDeviceCreateInfo(
            pNext=features,
            pQueueCreateInfos=[queue],
            ppEnabledExtensionNames=["VK_KHR_pipeline_executable_properties"],
        ),
        None,
    )
    executable_properties = vk.vkGetDeviceProcAddr(device, "vkGetPipelineExecutablePropertiesKHR")
    executable_statistics = vk.vkGetDeviceProcAddr(device, "vkGetPipelineExecutableStatisticsKHR")
    stage_bits = vk.VK_SHADER_STAGE_FRAGMENT_BIT
    bindings = [
        vk.VkDescriptorSetLayoutBinding(
            binding=binding,
            descriptorType=vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
            descriptorCount=1,
            stageFlags=stage_bits,
        )
        for binding in range(_SAMPLERS)
    ] + [
        vk.VkDescriptorSetLayoutBinding(
            binding=_UNIFORM_BLOCK,
            descriptorType=vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
            descriptorCount=1,
            stageFlags=stage_bits,
        )
    ]
    set_layout = vk.vkCreateDescriptorSetLayout(device, vk.VkDescriptorSetLayoutCreateInfo(pBindings=bindings), None)
    layout = vk.vkCreatePipelineLayout(device, vk.VkPipelineLayoutCreateInfo(pSetLayouts=[set_layout]), None)

    def module(code: bytes):
        return vk.vkCreateShaderModule(device, vk.VkShaderModuleCreateInfo(codeSize=len(code), pCode=code), None)

    vertex = module(_spirv(_VERTEX, "vert"))
    fixed_state = dict(
        pVertexInputState=vk.VkPipelineVertexInputStateCreateInfo(
            pVertexBindingDescriptions=[vk.VkVertexInputBindingDescription(binding=0, stride=8, inputRate=0)],
            pVertexAttributeDescriptions=[
                vk.VkVertexInputAttributeDescription(location=0, binding=0, format=vk.VK_FORMAT_R32G32_SFLOAT, offset=0)
            ],
        ),
        pInputAssemblyState=vk.VkPipelineInputAssemblyStateCreateInfo(topology=vk.VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP),
        pViewportState=vk.VkPipelineViewportStateCreateInfo(viewportCount=1, scissorCount=1),
        pRasterizationState=vk.VkPipelineRasterizationStateCreateInfo(
            polygonMode=vk.VK_POLYGON_MODE_FILL, cullMode=0, frontFace=0, lineWidth=1.0
        ),
        pMultisampleState=vk.VkPipelineMultisampleStateCreateInfo(rasterizationSamples=vk.VK_SAMPLE_COUNT_1_BIT),
        pColorBlendState=vk.VkPipelineColorBlendStateCreateInfo(
            pAttachments=[vk.VkPipelineColorBlendAttachmentState(colorWriteMask=0xF)]
        ),
        pDynamicState=vk.VkPipelineDynamicStateCreateInfo(
            pDynamicStates=[vk.VK_DYNAMIC_STATE_VIEWPORT, vk.VK_DYNAMIC_STATE_SCISSOR]
        ),
        layout=layout,
        flags=vk.VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR,
    )
    rendering = vk.VkPipelineRenderingCreateInfo(
        colorAttachmentCount=1, pColorAttachmentFormats=[vk.VK_FORMAT_R16G16B16A16_SFLOAT]
    )
    estimates = []
    for path in fragment_paths:
        fragment = module(_spirv(Path(path).read_text(encoding="utf-8"), "frag"))
        stages = [
            vk.VkPipelineShaderStageCreateInfo(stage=vk.VK_SHADER_STAGE_VERTEX_BIT, module=vertex, pName="main"),
            vk.VkPipelineShaderStageCreateInfo(stage=stage_bits, module=fragment, pName="main"),
        ]
        pipeline = vk.vkCreateGraphicsPipelines(
            device, None, 1, [vk.VkGraphicsPipelineCreateInfo(pNext=rendering, pStages=stages, **fixed_state)], None
        )[0]
        info = vk.VkPipelineInfoKHR(pipeline=pipeline)
        executables = executable_properties(device, info)
        index = next(i for i, executable in enumerate(executables) if executable.stages & stage_bits)
        statistics = executable_statistics(
            device, vk.VkPipelineExecutableInfoKHR(pipeline=pipeline, executableIndex=index)
        )
        values = {statistic.name: _statistic_value(vk, statistic) for statistic in statistics}
        missing = [name for name in STATISTICS if name not in values]
        if missing:
            raise RuntimeError(f"RADV did not report {missing} (it reported {sorted(values)})")
        estimates.append({name: values[name] for name in STATISTICS})
        vk.vkDestroyPipeline(device, pipeline, None)
        vk.vkDestroyShaderModule(device, fragment, None)
    return estimates, compiler


def _statistic_value(vk, statistic) -> int:
    """One statistic as an integer (RADV reports them all as 64-bit integers)."""
    if statistic.format == vk.VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
        return int(statistic.value.u64)
    if statistic.format == vk.VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
        return int(statistic.value.i64)
    if statistic.format == vk.VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR:
        return round(statistic.value.f64)
    return int(statistic.value.b32)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("shaders", nargs="+", type=Path, help="GLSL fragment shaders (#version 450)")
    parser.add_argument("--family", default=FAMILY, help=f"the AMD GPU family RADV compiles for (default {FAMILY})")
    parser.add_argument("--json", action="store_true", help="print a JSON list of the statistics, one per shader")
    # the child compiler_estimates starts in RADV's device-less environment (not for users)
    parser.add_argument("--compile-here", action="store_true", help=argparse.SUPPRESS)
    arguments = parser.parse_args(argv)
    if not arguments.compile_here:
        sources = {}
        for path in arguments.shaders:
            try:
                sources[str(path)] = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError) as error:
                parser.error(f"cannot read {path}: {error}")
        try:
            estimates, compiler = compiler_estimates(sources, arguments.family)
        except RuntimeError as error:
            print(f"gpu_compiler: error: {error}", file=sys.stderr)
            return 1
        results = list(estimates.values())
    else:
        try:
            results, compiler = _estimate([str(path) for path in arguments.shaders], arguments.family)
        except RuntimeError as error:
            print(error, file=sys.stderr)
            return 1
    if arguments.json:
        print(json.dumps({"compiler": compiler, "estimates": results}))
    else:
        print(f"ACO on {compiler}\n")
        print("| shader | " + " | ".join(STATISTICS) + " |\n|---|" + "---|" * len(STATISTICS))
        for path, result in zip(arguments.shaders, results):
            print(f"| {path} | " + " | ".join(str(result[name]) for name in STATISTICS) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
