"""The generated blocks of the docs: the lines between <!-- BEGIN GENERATED: NAME -->
and <!-- END GENERATED: NAME --> of a page, which a script writes and nobody types;
and the machine a measured block names."""
import datetime
import os
import platform
import sys


def markers(name):
    return "<!-- BEGIN GENERATED: %s -->" % name, "<!-- END GENERATED: %s -->" % name


def block(text, name):
    """The block's lines, or ValueError naming the missing markers."""
    begin, end = markers(name)
    if begin not in text or end not in text.split(begin, 1)[1]:
        raise ValueError("no '%s' ... '%s' block" % (begin, end))
    return text.split(begin, 1)[1].split(end, 1)[0].strip("\n").split("\n")


def replace_block(text, name, lines):
    """text with the block's lines replaced (ValueError as block())."""
    block(text, name)
    begin, end = markers(name)
    head, rest = text.split(begin, 1)
    tail = rest.split(end, 1)[1]
    return head + begin + "\n" + "\n".join(lines).rstrip("\n") + "\n" + end + tail


def write_block(page, name, lines, prog):
    """Writes the block into the page, or exits naming the page and the missing markers."""
    try:
        text = replace_block(open(page).read(), name, lines)
    except ValueError as e:
        sys.exit("%s: %s has %s" % (prog, page, e))
    open(page, "w").write(text)


def machine():
    """'2 cores (AMD EPYC), Linux 6.1.0': what a timing was measured on."""
    cpu = "unknown CPU"
    if os.path.exists("/proc/cpuinfo"):
        cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), cpu)
    return "%d cores (%s), %s %s" % (os.cpu_count(), cpu, platform.system(), platform.release())


def now_utc():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M")
