# SPDX-License-Identifier: BSD-3-Clause
# An OCI container image of the Debian package, as lewis and Renode users
# run their simulators; not part of `make check` (it downloads Debian's
# base packages, tens of MB, and takes minutes: mk/progress.py shows its
# stages as they come, the whole output goes to build/image.log):
#   make image         build/image/wsgsim-oci.tar from build/deb/wsgsim_*.deb
#                      (mk/image.sh: mmdebstrap, umoci; as root)
#   make image-tests   tests/image: the image's configuration (also as skopeo
#                      reads it for podman and docker), and wsgsim run
#                      from its root filesystem (unshare and chroot, as these
#                      machines cannot start containers) holding a GCL
#                      exchange, saving its settings, serving its page
# How to run the image elsewhere: README.md, "Container image".
IMAGE_DIR := build/image
IMAGE := $(IMAGE_DIR)/wsgsim-oci.tar
IMAGE_LOG := build/image.log
IMAGE_DEBS := mmdebstrap umoci skopeo
IMAGE_STAGES := ^(I: |image: )
WSGSIM_DEB := $(DEB_DIR)/wsgsim_$(DEB_VERSION)_$(DEB_ARCH).deb

.PHONY: image image-tests image-deps
## build the OCI image build/image/wsgsim-oci.tar from the .deb (as root)
image: $(IMAGE)

## install what the container image needs (mmdebstrap, umoci)
image-deps:
	@mk/deps.sh $(IMAGE_DEBS)

$(IMAGE): $(WSGSIM_DEB) mk/image.sh | image-deps
	@mkdir -p $(dir $(IMAGE_LOG))
	@/usr/bin/python3 mk/progress.py image $(IMAGE_LOG) '$(IMAGE_STAGES)' -- \
		mk/image.sh $(WSGSIM_DEB) $(IMAGE_DIR) $(DEB_VERSION)

## the image's configuration, and wsgsim run from its root filesystem
image-tests: $(IMAGE) | image-deps
	IMAGE=$(abspath $(IMAGE)) IMAGE_VERSION=$(DEB_VERSION) \
		python3 tests/run_suite.py image tests/image
