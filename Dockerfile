# isocorr on Debian 12, packages only. The build stage installs exactly the list that
# scripts/install-deps.sh installs in CI (deploy/packages-engine.txt and packages.txt),
# through the same script.
FROM debian:12 AS build
WORKDIR /src
COPY deploy/packages-engine.txt deploy/packages.txt deploy/
COPY scripts/install-deps.sh scripts/install-deps.sh
RUN ./scripts/install-deps.sh && rm -rf /var/lib/apt/lists/*
COPY . .
# The image runs on x86 CPUs with AVX2 and FMA (2013 on); --build-arg ISOCORR_ARCH=generic
# builds one for older machines (refinement about 1.4x slower). CMakeLists.txt says why.
ARG ISOCORR_ARCH=x86-64-v3
RUN cmake -S . -B /build -G Ninja -DCMAKE_BUILD_TYPE=Release -DISOCORR_BUILD_TESTS=OFF -DISOCORR_BUILD_SERVICE=ON \
      -DISOCORR_ARCH="${ISOCORR_ARCH}" \
 && cmake --build /build -j "$(nproc)" \
 && cmake --install /build --prefix /opt/isocorr

FROM debian:12-slim
COPY deploy/runtime-packages.txt /tmp/runtime-packages.txt
RUN apt-get update \
 && grep -v '^\s*#' /tmp/runtime-packages.txt | grep -v '^\s*$' \
    | xargs apt-get install -y --no-install-recommends \
 && rm -rf /var/lib/apt/lists/* /tmp/runtime-packages.txt \
 && useradd --system --create-home --home-dir /var/lib/isocorr isocorr \
 && install -d -o isocorr -g isocorr /var/lib/isocorr/data
COPY --from=build /opt/isocorr /opt/isocorr
ENV PATH=/opt/isocorr/bin:$PATH
USER isocorr
WORKDIR /var/lib/isocorr
# The server's durable store (meshes, job journal, results); mount a volume here.
VOLUME /var/lib/isocorr/data
EXPOSE 50051
# Inside the container the server listens on all interfaces so the published port reaches
# it; publish it on the host's loopback (see deploy/compose.yaml) unless TLS and a token are set.
HEALTHCHECK --interval=30s --timeout=5s --start-period=10s --retries=3 \
  CMD ["isocorr", "health", "--server", "127.0.0.1:50051", "--timeout", "4"]
ENTRYPOINT ["isocorr-server"]
CMD ["--listen", "0.0.0.0:50051", "--data-dir", "/var/lib/isocorr/data"]
