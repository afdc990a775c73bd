# facing-service: which tracked people face the robot, as a zenoh microservice.
# Configured only by FACING_* environment variables (see README, "Deploying with
# containers"), e.g. FACING_MODE=client FACING_CONNECT=tcp/router:7447.
#
# Offline builds: put prebuilt wheels (the project's and its dependencies', plus
# setuptools) in ./wheels and pass --build-arg PIP_NO_INDEX=1
# --build-arg PIP_FIND_LINKS=/src/wheels; pip reads both from the environment.
ARG BASE_IMAGE=python:3.12-slim

FROM ${BASE_IMAGE} AS build
ARG PIP_NO_INDEX
ARG PIP_FIND_LINKS
WORKDIR /src
COPY . .
# pip itself is not needed to run the service: uninstalled, the image stays under 400 MB.
RUN python3 -m venv /venv \
    && /venv/bin/pip install --no-cache-dir /src \
    && /venv/bin/python -m pip uninstall --yes --quiet pip

FROM ${BASE_IMAGE}
RUN groupadd --system --gid 10001 facing \
    && useradd --system --uid 10001 --gid 10001 --no-create-home --shell /usr/sbin/nologin facing
COPY --from=build /venv /venv
ENV PATH=/venv/bin:$PATH \
    PYTHONUNBUFFERED=1
USER 10001:10001
# A health check needs no flags: it reads the same FACING_* variables as the service.
# Under access control, set FACING_HEALTH_CONFIG to the health identity's zenoh config
# (examples/secure/health.json5): the service's own identity may not query its status.
HEALTHCHECK --interval=15s --timeout=10s --start-period=10s --retries=3 \
    CMD ["facing-service", "health", "--timeout", "3"]
# The CLI itself is PID 1 (exec form): SIGTERM reaches it and it exits 0 within 2 s.
ENTRYPOINT ["facing-service"]
CMD ["run"]
